"""train.py through Hydra (two iterations) and `realikea eval` on its checkpoint, with errors."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
from conftest import SMALL_RUN, TRAIN_PY_JOB

from realikea.cli import main
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.library_grid import cell_overrides, evaluate_grid, pooled, read_cells
from realikea.eval.protocol import EvalResult
from realikea.eval.setup import trained_cell
from realikea.eval.stats import wilson
from realikea.eval.table import CONTACT_STATS
from realikea.files import WORKSPACE, shown_path
from realikea.policies.checkpoint import CheckpointPolicy, slim_checkpoint
from realikea.tasks import observations
from realikea.tasks.contacts import STRATEGIES
from realikea.training.train import runner_config, train

SMALL = SMALL_RUN


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A two-iteration training run in its own Hydra run directory."""
    run_dir = tmp_path_factory.mktemp("run")
    library = tmp_path_factory.mktemp("library")
    args = [*SMALL, "logger=none", "agent.max_iterations=2", "agent.num_steps_per_env=8"]
    args += [f"paths.library={library}", f"hydra.run.dir={run_dir}"]
    out = subprocess.run(
        [sys.executable, "train.py", *args], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-3000:]
    assert "final checkpoint" in out.stdout
    return run_dir, library


def test_run_directory_holds_config_checkpoints_and_metrics(run):
    run_dir, _ = run
    assert (run_dir / ".hydra" / "config.yaml").is_file()
    assert sorted(p.name for p in run_dir.glob("model_*.pt")) == ["model_0.pt", "model_1.pt"]
    header = (run_dir / "metrics.csv").read_text().splitlines()[0]
    assert header == "iteration,tag,value"
    saved = torch.load(run_dir / "model_1.pt", weights_only=False)
    assert saved["infos"]["observation_layout"] == [list(t) for t in observations.LAYOUT]
    assert saved["infos"]["config"]["agent"]["max_iterations"] == 2


def test_a_checkpoint_evaluates_without_its_run_folder(run, tmp_path, capsys):
    run_dir, library = run
    alone = tmp_path / "model_1.pt"  # no .hydra/ and no observation_layout.json beside it
    shutil.copy(run_dir / "model_1.pt", alone)
    args = [*SMALL, f"paths.library={library}", "episodes=1"]
    assert main(["eval", f"policy.path={alone}", *args]) == 0
    assert json.loads(capsys.readouterr().out.strip().splitlines()[-1])["episodes"] == 1


def test_an_old_checkpoint_loads_its_layout_and_config_from_the_run_folder(run, tmp_path):
    run_dir, _ = run
    old = tmp_path / "run"
    shutil.copytree(run_dir, old)
    saved = torch.load(old / "model_1.pt", weights_only=False)
    saved["infos"] = None  # as rsl-rl saved them before checkpoints carried infos
    torch.save(saved, old / "model_1.pt")
    (old / "observation_layout.json").write_text(json.dumps(observations.LAYOUT))
    policy = CheckpointPolicy(old / "model_1.pt")
    assert policy.run_cfg.agent.max_iterations == 2
    (old / "observation_layout.json").unlink()
    with pytest.raises(RealIkeaError, match="carries no observation layout"):
        CheckpointPolicy(old / "model_1.pt")


def test_eval_prints_fractions_and_a_json_line(run, capsys):
    run_dir, library = run
    args = [*SMALL, f"paths.library={library}", "episodes=3"]
    assert main(["eval", f"policy.path={run_dir / 'model_1.pt'}", *args]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    summary = json.loads(lines[-1])
    keys = {"episodes", "fail", "partial", "success", "strategies", "success_strategies", "split"}
    keys |= {"failure_modes"}  # why each failed episode failed (realikea/tasks/failure_modes.py)
    assert set(summary) == keys
    assert summary["split"] == "train"  # the pinned part's own split
    assert any(" split=train resistance=" in line for line in lines)
    assert tuple(summary["strategies"]) == STRATEGIES
    assert sum(summary["strategies"].values()) == pytest.approx(1.0)
    assert summary["episodes"] == 3
    assert summary["fail"] + summary["partial"] + summary["success"] == pytest.approx(1.0)
    assert "| episodes | fail | partial | success |" in lines


def test_success_strategies_count_only_successful_episodes():
    outcomes = ["success", "success", "success", "fail", "partial"]
    labels = ["hook", "hook", "pinch", "pinch", "none"]
    episodes = [{"outcome": o, "strategy": s} for o, s in zip(outcomes, labels, strict=True)]
    summary = EvalResult(episodes).summary()
    assert summary["strategies"]["pinch"] == pytest.approx(0.4)
    assert summary["success_strategies"]["hook"] == pytest.approx(2 / 3)
    assert summary["success_strategies"]["pinch"] == pytest.approx(1 / 3)
    assert summary["success_strategies"]["none"] == 0.0
    failed = EvalResult([{"outcome": "fail", "strategy": "none"}]).summary()
    assert set(failed["success_strategies"].values()) == {0.0}
    assert "success_strategies" not in EvalResult([{"outcome": "fail"}]).summary()


def test_missing_checkpoint(capsys):
    assert main(["eval", "policy.path=/nonexistent/model_9.pt"]) == 2
    assert "checkpoint not found: /nonexistent/model_9.pt" in capsys.readouterr().err


def test_corrupt_checkpoint(run, tmp_path, capsys):
    run_dir, _ = run
    broken = tmp_path / "run"
    shutil.copytree(run_dir, broken)
    (broken / "model_1.pt").write_bytes(b"not a torch file")
    assert main(["eval", f"policy.path={broken / 'model_1.pt'}"]) == 2
    assert "not a readable rsl-rl checkpoint" in capsys.readouterr().err


def test_checkpoint_from_another_observation_layout(run, tmp_path, capsys):
    run_dir, _ = run
    other = tmp_path / "run"
    shutil.copytree(run_dir, other)
    saved = torch.load(other / "model_1.pt", weights_only=False)
    saved["infos"]["observation_layout"] = [["tcp_pos", 3], ["gripper_width", 1]]
    torch.save(saved, other / "model_1.pt")
    assert main(["eval", f"policy.path={other / 'model_1.pt'}"]) == 2
    assert "an observation layout this code cannot give" in capsys.readouterr().err
    # terms this code has, but not the ones the actor's weights were trained on
    saved["infos"]["observation_layout"] = [["tcp_pos", 3], ["opening", 1]]
    torch.save(saved, other / "model_1.pt")
    assert main(["eval", f"policy.path={other / 'model_1.pt'}"]) == 2
    assert "actor does not match the run's network" in capsys.readouterr().err


def test_resume_continues_from_the_checkpoint(run, tmp_path):
    run_dir, library = run
    resumed = tmp_path / "resumed"
    args = [*SMALL, "logger=none", "agent.max_iterations=1", "agent.num_steps_per_env=8"]
    args += [f"paths.library={library}", f"hydra.run.dir={resumed}"]
    args += [f"train.resume={run_dir / 'model_1.pt'}"]
    out = subprocess.run(
        [sys.executable, "train.py", *args], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-3000:]
    # rsl-rl restarts at the checkpoint's iteration (1), not at 0 (its `.../time` tags count
    # seconds from the launch, not iterations)
    rows = (resumed / "metrics.csv").read_text().splitlines()[1:]
    assert {int(r.split(",")[0]) for r in rows if not r.split(",")[1].endswith("/time")} == {1}
    assert (resumed / "model_1.pt").is_file() and not (resumed / "model_0.pt").exists()


@pytest.mark.slow
def test_joblib_multirun_over_collision_sources(tmp_path):
    """The fidelity ablation as one line, jobs in parallel (env workers inside loky workers)."""
    args = [*SMALL, "env.num_workers=1", "logger=none", "agent.max_iterations=1"]
    args += ["agent.num_steps_per_env=4", "collision=coacd,hull", "hydra/launcher=joblib"]
    args += [f"paths.library={tmp_path / 'library'}", f"hydra.sweep.dir={tmp_path / 'sweep'}"]
    out = subprocess.run(
        [sys.executable, "train.py", "-m", *args], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-3000:]
    assert (tmp_path / "sweep" / "0" / "model_0.pt").is_file()
    assert (tmp_path / "sweep" / "1" / "model_0.pt").is_file()


def test_sweep_evaluates_every_checkpoint_under_three_modes(run, capsys):
    run_dir, library = run
    args = [f"paths.library={library}", "episodes=2", "env.num_workers=0"]
    assert main(["eval", "sweep", str(run_dir), *args]) == 0
    out = capsys.readouterr().out
    rows = (run_dir / "sweep" / "sweep.csv").read_text().splitlines()
    assert rows[0].startswith("iteration,success_smooth,return_smooth,")
    assert [r.split(",")[0] for r in rows[1:]] == ["0", "1"]
    assert (run_dir / "sweep" / "sweep.png").stat().st_size > 10_000
    assert "most robust checkpoint: " in out and "**most robust**" in out
    table = (run_dir / "sweep" / "sweep.md").read_text()
    assert "split train" in table and "env.seed=2000" in table  # the validation draw
    lo, hi = wilson(round(float(rows[1].split(",")[7]) * 6), 6)  # mean S over 3 modes x 2
    assert f"[{lo:.2f}, {hi:.2f}]" in table.splitlines()[6]
    # rerun with the same overrides: every (checkpoint, mode) comes from results.jsonl
    assert len((run_dir / "sweep" / "results.jsonl").read_text().splitlines()) == 6
    assert main(["eval", "sweep", str(run_dir), *args]) == 0
    again = capsys.readouterr().out
    assert "iteration 0" not in again.split("# Checkpoint sweep")[0]
    assert (run_dir / "sweep" / "sweep.md").read_text() == table


def test_a_committed_table_names_a_run_of_the_checkout_relative_to_it():
    name = "experiments/fidelity_ablation/results/grid/paper_hull_high_two_point_s0"
    assert shown_path(WORKSPACE / name) == name
    assert shown_path(Path("/elsewhere/run")) == "/elsewhere/run"


def test_a_sweep_on_the_test_parts_is_refused_before_any_work(run, capsys):
    run_dir, library = run
    before = sorted((run_dir / "sweep").glob("*")) if (run_dir / "sweep").is_dir() else None
    for split in ("test", "all"):
        args = [f"paths.library={library}", f"asset.split={split}"]
        assert main(["eval", "sweep", str(run_dir), *args]) == 2
        err = capsys.readouterr().err
        assert f"asset.split={split}: a checkpoint sweep selects a policy" in err
    after = sorted((run_dir / "sweep").glob("*")) if (run_dir / "sweep").is_dir() else None
    assert after == before


def test_sweep_without_checkpoints_is_a_clear_error(tmp_path, capsys):
    assert main(["eval", "sweep", str(tmp_path)]) == 2
    assert "no checkpoints" in capsys.readouterr().err


def test_table_writes_the_table2_layout(tmp_path, run, capsys):
    _, library = run
    args = [
        "asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20", "env.num_workers=0",
        "task.episode_seconds=1.5", f"paths.library={library}", "episodes=2",
        "table.policies=[heuristic_pull]", "table.categories=[two_point]",
        "table.resistances=[smooth,high]", f"table.out={tmp_path}",
    ]  # fmt: skip
    assert main(["eval", "table", *args]) == 0
    csv_rows = (tmp_path / "table2.csv").read_text().splitlines()
    assert len(csv_rows) == 3 and "strategy_pinch" in csv_rows[0]
    markdown = (tmp_path / "table2.md").read_text()
    assert "## Two-point handles" in markdown
    assert "| Policy | smooth F | P | S | high F | P | S |" in markdown
    assert "split" in csv_rows[0] and "split=train" in markdown.splitlines()[0]
    assert markdown.count("| heuristic_pull |") == 3  # the F/P/S row and two strategy rows


def test_table_refuses_checkpoints_and_unknown_policies(capsys):
    assert main(["eval", "table", "table.policies=[checkpoint]"]) == 2
    assert "realikea eval sweep" in capsys.readouterr().err
    assert main(["eval", "policy=nonsense"]) == 2
    assert "nonsense" in capsys.readouterr().err


def test_realikea_train_composes_what_train_py_composes(train_py_job):
    out = subprocess.run(
        [sys.executable, "-m", "realikea.cli", "train", *TRAIN_PY_JOB],
        cwd=WORKSPACE, capture_output=True, text=True,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout == train_py_job and "category: knob" in train_py_job


def test_a_generalist_trains_two_iterations_on_a_mixed_draw_of_kinds(tmp_path):
    """asset=all draws by turns over category x kind: one part on a drawer, a door and the flap
    (one run of it: pipeline=none; tests/test_training_pipeline.py trains its stages)."""
    args = ["pipeline=none", "asset.part=tp_round_bar_128", "dr=fixed", "env.num_envs=3"]
    args += ["env.num_workers=0"]
    args += ["task.episode_seconds=1.5", "logger=none", "agent.max_iterations=2"]
    args += ["agent.num_steps_per_env=8", f"paths.library={tmp_path / 'library'}"]
    args += ["agent.init_at_random_ep_len=false"]  # every first episode ends at step 15
    args += [f"hydra.run.dir={tmp_path / 'run'}"]
    out = subprocess.run(
        [sys.executable, "train.py", *args], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-3000:]
    built = sorted(
        p.name.split("__")[1].split("_")[0] for p in (tmp_path / "library").iterdir() if p.is_dir()
    )
    assert built == ["door", "drawer", "flap"]
    assert (tmp_path / "run" / "model_1.pt").is_file()
    tags = {row.split(",")[1] for row in (tmp_path / "run" / "metrics.csv").read_text().split()}
    # the 15-step episodes end in the second iteration: success is logged per category x kind
    assert {f"/success/two_point_{k}" for k in ("door", "drawer", "flap")} <= tags


def test_a_checkpoint_of_the_appendix_layout_reads_its_terms_from_todays_observation():
    """Checkpoints before the articulation terms (28-D) still act, on their own terms."""
    path = WORKSPACE / "experiments/learning/results/two_point_drawer_smooth_coacd/model_999.pt"
    policy = CheckpointPolicy(path)
    assert policy.index.tolist() == list(range(28))
    obs = np.random.default_rng(0).normal(size=(3, observations.SIZE))
    changed = obs.copy()
    changed[:, 28:] += 1.0  # the terms it was not trained on do not reach it
    np.testing.assert_array_equal(policy.act(obs), policy.act(changed))
    assert policy.act(obs).shape == (3, 5)


def test_a_layout_with_an_unknown_term_is_refused_by_name():
    with pytest.raises(KeyError, match="'gripper_width' of size 1"):
        observations.selector([("tcp_pos", 3), ("gripper_width", 1)])


def test_the_grid_evaluation_appends_a_cell_and_skips_it_when_run_again(run, tmp_path, load_script):
    run_dir, library = run
    results = tmp_path / "cells.jsonl"
    pin = ["asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20", f"paths.library={library}"]
    cell = {"kinds": ("drawer",), "categories": ("two_point",), "modes": ("smooth",)}
    cells = evaluate_grid(run_dir / "model_1.pt", results, 2, 1000, **cell, extra=pin)
    record = cells[("drawer", "two_point", "smooth")]
    assert record["episodes"] == 2 and record["scene"] == "kitchen"
    assert record["split"] == "train"  # the pinned part's own split
    assert "asset.split=test" in record["command"] and "env.seed=1000" in record["command"]
    # the contact statistics of its episodes that pulled (null where none did)
    assert set(record["contacts"]) == set(CONTACT_STATS) and 0 <= record["pulled_episodes"] <= 2
    assert all((v is None) == (record["pulled_episodes"] == 0) for v in record["contacts"].values())
    evaluate_grid(run_dir / "model_1.pt", results, 2, 1000, **cell, extra=pin)
    assert len(results.read_text().splitlines()) == 1
    table = load_script("experiments/generalist/cell_tables.py").success_table(read_cells(results))
    assert "| drawer | two_point |" in table and "[" in table


def test_a_grid_cell_puts_the_arm_where_the_checkpoint_was_trained(tmp_path):
    """A run whose kitchen placements differ from today's is evaluated with its own (a changed
    placement would move its arm); a checkpoint with no run config beside it, with today's."""
    (tmp_path / ".hydra").mkdir()
    (tmp_path / ".hydra" / "config.yaml").write_text(
        "scene:\n  name: kitchen\n  robot:\n    placements: []\n"
    )
    args = ("drawer", "finger_pull", "high", 2, 1000, ["episodes=3"])
    overrides = cell_overrides(tmp_path / "model_1.pt", *args)
    assert overrides[-2:] == ["scene.robot.placements=[]", "episodes=3"]  # the command line last
    assert "scene.robot.placements=[]" not in cell_overrides(tmp_path / "sub" / "model.pt", *args)


def test_the_table_names_the_top_failure_mode_in_high_and_a_dash_without_one(load_script):
    def record(mode, failures):
        return {"episodes": 50, "success": 0.2, "partial": 0.3, "mode": mode,
                "strategies": {"pinch": 0.6, "hook": 0.1}, **failures}  # fmt: skip

    slips = {"failure_modes": {"slip": 0.56, "narrow_clearance": 0.1}}
    cells = {("door", "knob", m): record(m, slips) for m in ("smooth", "normal", "high")}
    cells |= {("flap", "knob", m): record(m, {}) for m in ("smooth", "normal", "high")}
    lines = load_script("experiments/generalist/cell_tables.py").success_table(cells).splitlines()
    assert lines[0].endswith("| strategy (high) | failure mode (high) |")
    (door,) = [x for x in lines if x.startswith("| door | knob |")]
    (flap,) = [x for x in lines if x.startswith("| flap | knob |")]
    assert door.endswith("| pinch 0.60 | slip 0.56 |")
    assert flap.endswith("| pinch 0.60 | – |")  # evaluated before the failure modes existed


def test_pooling_counts_every_cell_of_a_mode_or_of_one_kind():
    cells = {
        ("door", "knob", "high"): {"episodes": 50, "success": 0.2},
        ("door", "two_point", "high"): {"episodes": 50, "success": 0.4},
        ("flap", "knob", "high"): {"episodes": 20, "success": 1.0},
        ("flap", "knob", "smooth"): {"episodes": 50, "success": 1.0},
    }
    assert pooled(cells, "high") == (50, 120)
    assert pooled(cells, "high", "door") == (30, 100)
    assert pooled(cells, "high", "drawer") == (0, 0)


def test_a_slim_checkpoint_acts_like_its_source(run, tmp_path):
    run_dir, _ = run
    slim = slim_checkpoint(run_dir / "model_1.pt", tmp_path / "slim" / "model_1.pt")
    assert set(torch.load(slim, weights_only=False)) == {"actor_state_dict", "iter", "infos"}
    assert slim.stat().st_size < 0.5 * (run_dir / "model_1.pt").stat().st_size
    obs = np.random.default_rng(1).normal(size=(4, observations.SIZE))
    full, small = CheckpointPolicy(run_dir / "model_1.pt"), CheckpointPolicy(slim)
    np.testing.assert_array_equal(full.act(obs), small.act(obs))
    assert small.run_cfg.agent.max_iterations == 2


def test_a_sampled_checkpoint_acts_on_its_gaussian_from_its_seed(run):
    """`policy.sample`: the mean plus the learned std times noise drawn from the seed, the same
    for the same seed; the mean action otherwise."""
    run_dir, _ = run
    obs = np.random.default_rng(1).normal(size=(4, observations.SIZE))
    mean = CheckpointPolicy(run_dir / "model_1.pt")
    first, again = (CheckpointPolicy(run_dir / "model_1.pt", sample_seed=7) for _ in range(2))
    np.testing.assert_array_equal(first.act(obs), again.act(obs))
    noise = first.act(obs) - mean.act(obs)
    std = mean.actor.distribution.std_param.detach().numpy()
    assert np.all(np.abs(noise).mean(axis=0) > 0.05 * std)  # drawn, at the std's scale
    cfg = load_config([f"policy.path={run_dir / 'model_1.pt'}", "env.seed=7"], "eval")
    assert CheckpointPolicy.from_config(cfg).noise is None
    cfg.policy.sample = True
    fresh = CheckpointPolicy(run_dir / "model_1.pt", sample_seed=7)  # the noise's first draw
    np.testing.assert_array_equal(CheckpointPolicy.from_config(cfg).act(obs), fresh.act(obs))
    cfg.policy.sample = "yes"
    with pytest.raises(RealIkeaError, match="policy.sample=yes: use true or false"):
        CheckpointPolicy.from_config(cfg)


@pytest.mark.parametrize("spread", [True, False])
def test_episode_starts_spread_after_the_first_rollout(run, tmp_path, spread):
    """init_at_random_ep_len: 15-step episodes, 8-step rollouts. In lockstep no episode ends in
    the first rollout; spread, some do (each env starts at a random point of its first one,
    drawn with the run's seed)."""
    _, library = run
    cfg = load_config(
        [*SMALL, "env.num_envs=4", "logger=none", "agent.max_iterations=2",
         "agent.num_steps_per_env=8", f"agent.init_at_random_ep_len={spread}",
         f"paths.library={library}"]
    )  # fmt: skip
    train(cfg, tmp_path)
    # rsl-rl logs the mean episode length of the iterations in which an episode ended (the ends
    # of the shortened first episodes included)
    rows = (tmp_path / "metrics.csv").read_text().splitlines()
    ended = {int(row.split(",")[0]) for row in rows if ",Train/mean_episode_length," in row}
    assert (0 in ended) == spread
    assert 1 in ended  # by step 16 every lockstep episode has ended too


def test_resuming_under_another_reward_variant_is_refused_naming_both(run, tmp_path, capsys):
    run_dir, library = run
    args = [*SMALL, "logger=none", "task/reward=appendix", f"paths.library={library}"]
    args += [f"hydra.run.dir={tmp_path}", f"train.resume={run_dir / 'model_1.pt'}"]
    out = subprocess.run(
        [sys.executable, "train.py", *args], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode != 0
    assert "trained on the 'gated' reward variant, this run asks for 'appendix'" in out.stderr
    assert not list(tmp_path.glob("model_*.pt"))


def test_an_unknown_reward_variant_fails_before_any_work(tmp_path):
    cfg = load_config([*SMALL, f"paths.library={tmp_path / 'library'}"])
    cfg.task.reward.variant = "shaped"
    with pytest.raises(RealIkeaError, match="use one of appendix, gated"):
        train(cfg, tmp_path / "run")
    assert not (tmp_path / "library").exists() and not (tmp_path / "run").exists()


def test_an_unknown_console_fails_before_any_work(tmp_path):
    cfg = load_config([*SMALL, f"paths.library={tmp_path / 'library'}", "train.console=tqdm"])
    with pytest.raises(RealIkeaError, match="train.console=tqdm: use one of bar, report"):
        train(cfg, tmp_path / "run")
    assert not (tmp_path / "library").exists() and not (tmp_path / "run").exists()


def test_trained_cell_reads_what_a_run_trained_on_from_its_overrides(tmp_path):
    (tmp_path / ".hydra").mkdir()
    (tmp_path / ".hydra/overrides.yaml").write_text(
        "- task/reward=gated\n- collision=hull\n- asset=knob\n- resistance=smooth\n"
        "- env.seed=1\n- asset.kind=drawer\n- scene=kitchen\n- agent.max_iterations=400\n"
    )
    assert trained_cell(tmp_path) == [
        "collision=hull", "asset=knob", "resistance=smooth", "asset.kind=drawer", "scene=kitchen",
    ]  # fmt: skip
    with pytest.raises(RealIkeaError, match="no Hydra overrides"):
        trained_cell(tmp_path / "elsewhere")


def test_min_std_is_a_floor_under_the_policys_action_std():
    assert "std_range" not in runner_config(load_config())["actor"]["distribution_cfg"]
    floored = runner_config(load_config(["agent.min_std=0.4"]))["actor"]["distribution_cfg"]
    assert floored["std_range"] == [0.4, 1e6]
    with pytest.raises(RealIkeaError, match=r"agent.min_std=2.0: use a value in \(0"):
        runner_config(load_config(["agent.min_std=2.0"]))


def test_max_std_is_a_ceiling_over_the_policys_action_std():
    capped = runner_config(load_config(["agent.max_std=0.1"]))["actor"]["distribution_cfg"]
    assert capped["std_range"] == [1e-6, 0.1]
    both = runner_config(load_config(["agent.min_std=0.05", "agent.max_std=0.1"]))
    assert both["actor"]["distribution_cfg"]["std_range"] == [0.05, 0.1]
    with pytest.raises(RealIkeaError, match=r"agent.max_std=0.1: use a value of at least"):
        runner_config(load_config(["agent.min_std=0.4", "agent.max_std=0.1"]))
    with pytest.raises(RealIkeaError, match=r"agent.max_std=0.0: use a value of at least"):
        runner_config(load_config(["agent.max_std=0.0"]))
