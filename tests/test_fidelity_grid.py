"""The fidelity grid: its experiment config, the runs it plans and what a finished run keeps."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from omegaconf import OmegaConf

from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.runs import check_eval_spec, eval_overrides
from realikea.eval.setup import eval_setup
from realikea.files import WORKSPACE
from realikea.policies.full_squeeze import FullSqueeze
from realikea.rewards import variant_name
from realikea.runs.records import mode_overrides
from realikea.training.metrics import join_launches


@pytest.fixture(scope="module")
def fidelity_grid(load_script):
    return load_script("experiments/fidelity_ablation/grid_runs.py")


def _planned(fidelity_grid, seeds=(0, 1), paper=False, **axes):
    return fidelity_grid.planned(**{**fidelity_grid.AXES, **axes}, seeds=seeds, paper=paper)


def test_the_experiment_trains_in_the_kitchen_on_train_parts_and_evaluates_on_test_parts(
    fidelity_grid,
):
    cfg = load_config(["+experiment=fidelity_grid", "asset=knob"])
    assert cfg.scene.name == "kitchen" and cfg.asset.split == "train"
    assert cfg.asset.kind == "drawer" and cfg.env.num_envs == 64
    assert cfg.agent.max_iterations == 900 and cfg.dr.switch_iteration == 300
    assert cfg.train.eval_after.split == "test" and cfg.train.eval_after.episodes == 50
    assert cfg.task.reward.w_open2 == 0.0  # the appendix's, not the generalist's 2.0
    assert cfg.task.reward.variant == "appendix" and not cfg.agent.init_at_random_ep_len
    assert cfg.train.eval_after.collision == "coacd"  # every run on the faithful geometry
    assert cfg.agent.max_iterations == fidelity_grid.ITERATIONS


def test_a_bad_end_of_training_evaluation_is_refused_before_training(tmp_path):
    run = ["+experiment=fidelity_grid", "asset=two_point", "resistance=high"]
    check_eval_spec(load_config(run).train.eval_after, run)  # the grid's own spec composes
    bad = {
        "train.eval_after.collision=cylinder": "cylinder",
        "train.eval_after.split=heldout": "heldout",
        "train.eval_after.dr=sometimes": "sometimes",
        "train.eval_after.resistances=[high,sticky]": "sticky",
        "train.eval_after.episodes=0": "episodes=0",
    }
    for override, named in bad.items():
        with pytest.raises(RealIkeaError, match=f"train.eval_after: .*{named}"):
            check_eval_spec(load_config([*run, override]).train.eval_after, run)
    # train.py checks it first: the run fails in seconds and writes no checkpoint
    out = subprocess.run(
        [sys.executable, "train.py", *run, "train.eval_after.collision=cylinder",
         f"hydra.run.dir={tmp_path}"],
        cwd=WORKSPACE, capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert out.returncode != 0 and "train.eval_after" in out.stderr
    assert not list(tmp_path.glob("model_*.pt"))


def test_runs_go_seed_by_seed_and_bad_axis_values_are_refused(fidelity_grid):
    runs = _planned(fidelity_grid)
    assert len(runs) == 2 * 3 * 3 * 2
    assert {r.seed for r in runs[:18]} == {0} and runs[0].name == "coacd_high_two_point_s0"
    paper = _planned(fidelity_grid, paper=True)[0]
    assert paper.name == "paper_coacd_high_two_point_s0" and paper.iterations == 1500
    assert "dr.switch_iteration=900" in paper.overrides
    with pytest.raises(RealIkeaError, match="unknown categories bogus"):
        _planned(fidelity_grid, categories=["bogus"])
    with pytest.raises(RealIkeaError, match="seeds"):
        _planned(fidelity_grid, seeds=[-1])


def test_a_stopped_run_continues_from_its_last_checkpoint_and_finishes_with_eval_json(
    tmp_path, fidelity_grid
):
    queue = fidelity_grid.grid_queue(tmp_path / "work", tmp_path / "kept")
    run = _planned(fidelity_grid, seeds=[0])[0]
    assert not any(a.startswith("train.resume=") for a in queue.command(run))
    run_dir = tmp_path / "work" / run.name
    run_dir.mkdir(parents=True)
    for it in (0, 50, 150):
        (run_dir / f"model_{it}.pt").write_bytes(b"")
    command = queue.command(run)
    assert f"train.resume={run_dir / 'model_150.pt'}" in command
    assert f"agent.max_iterations={fidelity_grid.ITERATIONS - 150}" in command
    assert queue.state(run) == "stopped"
    (run_dir / "model_899.pt").write_bytes(b"")
    assert queue.state(run) == "stopped"  # a grid run is finished by its evaluation
    (run_dir / "eval.json").write_text("{}")
    assert queue.state(run) == "finished"


def test_seed_0_of_the_papers_schedule_keeps_the_checkpoints_the_sweep_needs(fidelity_grid):
    found = [(it, Path(f"model_{it}.pt")) for it in (0, 50, 100, 150, 200, 1499)]
    paper = _planned(fidelity_grid, seeds=[0, 1], paper=True)
    swept = [r.seed == 0 and (r.category, r.resistance) == ("two_point", "high") for r in paper]
    assert [r.swept for r in paper] == swept and paper[0].swept and sum(swept) == 2  # a source
    kept = [p.name for p in fidelity_grid.kept_checkpoints(paper[0], found)]
    assert kept == ["model_0.pt", "model_100.pt", "model_200.pt", "model_1499.pt"]
    assert fidelity_grid.kept_checkpoints(paper[-1], found) == [Path("model_1499.pt")]  # seed 1
    grid_run = _planned(fidelity_grid, seeds=[0])[0]
    assert not grid_run.swept and fidelity_grid.kept_checkpoints(grid_run, found) == [found[-1][1]]


def test_a_kept_runs_eval_commands_name_the_checkpoint_git_holds(fidelity_grid):
    trained = fidelity_grid.WORK / "hull_high_knob_s0" / "model_899.pt"
    command = f"realikea eval policy=checkpoint policy.path={trained} resistance=high episodes=50"
    report = {"checkpoint": "model_899.pt", "modes": {"high": {"command": command}}}
    kept = fidelity_grid.kept_eval(report, fidelity_grid.KEPT / "hull_high_knob_s0")
    assert kept["modes"]["high"]["command"] == (
        "realikea eval policy=checkpoint "
        "policy.path=experiments/fidelity_ablation/results/grid/hull_high_knob_s0/model_899.pt "
        "resistance=high episodes=50"
    )


def test_a_sweep_over_a_group_value_that_does_not_exist_fails_before_writing(tmp_path):
    out = subprocess.run(
        [sys.executable, "train.py", "-m", "+experiment=fidelity_grid", "asset=bogus",
         "hydra/launcher=basic", f"hydra.sweep.dir={tmp_path / 'sweep'}"],
        cwd=WORKSPACE, capture_output=True, text=True,
    )  # fmt: skip
    assert out.returncode != 0
    assert "Could not find 'asset/bogus'" in out.stderr and "two_point" in out.stderr
    assert not (tmp_path / "sweep").exists()


def test_the_report_names_runs_without_eval_json_and_refuses_an_empty_root(
    tmp_path, capsys, load_script
):
    report = load_script("experiments/fidelity_ablation/fidelity_report/report.py").report
    (tmp_path / "runs" / "coacd_high_knob_s0" / ".hydra").mkdir(parents=True)
    (tmp_path / "runs" / "coacd_high_knob_s0" / ".hydra" / "config.yaml").write_text("a: 1\n")
    with pytest.raises(RealIkeaError, match="no finished runs"):
        report([tmp_path / "runs"], tmp_path / "out")
    assert "no eval.json yet" in capsys.readouterr().err
    with pytest.raises(RealIkeaError, match="no such directory"):
        report([tmp_path / "missing"], tmp_path / "out")
    assert not (tmp_path / "out").exists()


def test_a_resumed_runs_repeated_iteration_is_kept_once_from_the_later_launch():
    lines = ["iteration,tag,value", "598,/episode/success,0.5", "599,/episode/success,0.6",
             "12,Train/mean_reward/time,7", "599,/episode/success,0.7",
             "12,Train/mean_reward/time,9", "600,/episode/success,0.8"]  # fmt: skip
    assert join_launches(lines) == [
        "iteration,tag,value", "598,/episode/success,0.5", "12,Train/mean_reward/time,7",
        "599,/episode/success,0.7", "12,Train/mean_reward/time,9", "600,/episode/success,0.8",
    ]  # fmt: skip
    # a row only the earlier launch wrote at an iteration the later one repeated goes too
    earlier_only = [*lines[:3], "599,/success/knob_drawer,0.1", *lines[3:]]
    assert join_launches(earlier_only) == join_launches(lines)


def test_two_runs_are_compared_mode_by_mode_with_intervals(tmp_path, load_script):
    comparison_lines = load_script(
        "experiments/fidelity_ablation/fidelity_report/compare.py"
    ).comparison_lines
    for name, success in (("a", 0.46), ("b", 0.70)):
        (tmp_path / name).mkdir()
        modes = {"high": {"success": success, "episodes": 50}}
        (tmp_path / name / "eval.json").write_text(json.dumps({"modes": modes}))
    row = comparison_lines(tmp_path / "a", tmp_path / "b")[-1]
    # 23 of 50 against 35 of 50: Newcombe's interval excludes zero
    assert (
        row
        == "| high | 0.46 [0.33, 0.60] | 0.70 [0.56, 0.81] | -0.24 [-0.41, -0.05] | significant |"
    )
    with pytest.raises(RealIkeaError, match="no eval.json"):
        comparison_lines(tmp_path, tmp_path / "b")


def test_the_squeeze_check_closes_only_what_the_policy_closes_and_reads_the_runs_draw(tmp_path):
    class Fixed:
        def reset(self, env_ids, facts):
            pass

        def act(self, obs):
            return np.array([[0.0, 0.0, 0.0, 0.0, -0.5], [0.0, 0.0, 0.0, 0.0, 0.3]])

    squeezed = FullSqueeze(Fixed())
    action = squeezed.act(np.zeros((2, 3)))
    assert action[:, 4].tolist() == [-1.0, 0.3] and squeezed.closing == [-0.5]
    with pytest.raises(RealIkeaError, match="no eval.json"):
        mode_overrides(tmp_path, "high", 50)
    command = "realikea eval policy=checkpoint policy.path=x.pt resistance=smooth episodes=50"
    (tmp_path / "eval.json").write_text(json.dumps({"modes": {"smooth": {"command": command}}}))
    with pytest.raises(RealIkeaError, match="not high"):
        mode_overrides(tmp_path, "high", 50)
    assert mode_overrides(tmp_path, "smooth", 8) == [
        "policy=checkpoint", "policy.path=x.pt", "resistance=smooth", "episodes=8"
    ]  # fmt: skip


GRID_RUN = WORKSPACE / "experiments/fidelity_ablation/results/grid/coacd_high_two_point_s0"


def test_a_committed_grid_checkpoint_evaluates_on_the_reward_it_was_trained_on():
    """Its config names no reward variant (it predates them): the appendix, w_open2 = 0."""
    overrides = eval_overrides(
        list(OmegaConf.load(GRID_RUN / ".hydra/overrides.yaml")),
        GRID_RUN / "model_899.pt",
        "high",
        OmegaConf.load(GRID_RUN / ".hydra/config.yaml").train.eval_after,
    )
    cfg, _ = eval_setup(overrides)
    assert variant_name(cfg.task.reward) == "appendix" and cfg.task.reward.w_open2 == 0.0


# the last commit before reward variants: what the appendix variant must reproduce
BEFORE_VARIANTS = "f2cbe57"


def _rerun(code: Path, run: Path) -> dict:
    """`realikea eval rerun RUN` with the package at `code`; the run's new eval.json."""
    out = subprocess.run(
        [sys.executable, "-m", "realikea.cli", "eval", "rerun", str(run)],
        cwd=code, capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(code)},
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads((run / "eval.json").read_text())


@pytest.mark.slow
def test_the_committed_grids_eval_rerun_is_unchanged_by_reward_variants(tmp_path):
    """`realikea eval rerun` of a committed grid run gives the same eval.json as the code before
    reward variants, on the same machine and library (3 modes x 50 episodes on the test parts,
    twice: about 7 min on the 2 cores). Against the committed eval.json itself a fresh machine's
    library can differ (its CoACD build): rerun with the code before variants on such a machine,
    the labels of smooth and normal matched it and high gave 0.96 against 0.94."""
    before = tmp_path / "before"
    subprocess.run(
        ["git", "worktree", "add", "--detach", str(before), BEFORE_VARIANTS],
        cwd=WORKSPACE, check=True, capture_output=True,
    )  # fmt: skip
    try:
        for shared in ("outputs", ".cache"):  # the same built library and mesh cache
            (WORKSPACE / shared).mkdir(exist_ok=True)
            (before / shared).symlink_to(WORKSPACE / shared)
        runs = {}
        for name in ("before", "now"):
            runs[name] = tmp_path / name / GRID_RUN.name
            shutil.copytree(GRID_RUN, runs[name], ignore=shutil.ignore_patterns("videos"))
        expected = _rerun(before, runs["before"])["modes"]
        again = _rerun(WORKSPACE, runs["now"])["modes"]
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", str(before)], cwd=WORKSPACE)
    for mode, entry in expected.items():
        for key in ("fail", "partial", "success", "strategies", "failure_modes", "mean_return"):
            assert again[mode][key] == entry[key], (mode, key)
