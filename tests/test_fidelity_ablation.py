"""The fidelity-ablation experiment: config and sweep axes, a tiny multirun through it with the
end-of-training evaluation (eval.json), the report, and (opt-in) the Ray launcher."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from types import SimpleNamespace

import mujoco
import pytest
import yaml
from hydra import compose, initialize_config_dir
from hydra.core.global_hydra import GlobalHydra
from hydra.core.override_parser.overrides_parser import OverridesParser
from omegaconf import OmegaConf

from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.runs import eval_overrides
from realikea.eval.stats import diff_interval, seed_difference, seed_interval
from realikea.files import CONF_DIR, WORKSPACE
from realikea.rewards import store_configs
from realikea.runs.curves import iterations_to_success, last_windows, trailing_mean
from realikea.runs.records import _trained_iterations, command_overrides, schedule
from realikea.tasks.contacts import STRATEGIES
from realikea.tasks.failure_modes import FAILURE_MODES
from realikea.tasks.randomization import two_phase_switch

REPORT = "experiments/fidelity_ablation/fidelity_report"
TINY = [
    "asset=two_point",
    "asset.part=tp_round_bar_128",
    "asset.base=drawer_w60_h20",
    "resistance=smooth",
    "env.num_envs=2",
    "env.num_workers=0",
    "task.episode_seconds=1.5",
    "agent.max_iterations=2",
    "agent.num_steps_per_env=8",
    "train.eval_after.episodes=2",
]


@pytest.fixture(scope="module")
def study(load_script):
    """The study's report modules (experiments/fidelity_ablation/fidelity_report/), by name."""
    return SimpleNamespace(
        **{m: load_script(f"{REPORT}/{m}.py") for m in ("cells", "report", "tables", "videos")}
    )


def hydra_config(overrides):
    GlobalHydra.instance().clear()
    store_configs()
    try:
        with initialize_config_dir(str(CONF_DIR), version_base="1.3"):
            return compose("config", overrides=overrides, return_hydra_config=True)
    finally:
        GlobalHydra.instance().clear()


def test_experiment_sets_two_phase_training_and_the_evaluation():
    cfg = load_config(["+experiment=fidelity_ablation"])
    assert cfg.dr.mode == "two_phase" and 0 < cfg.dr.switch_iteration < cfg.agent.max_iterations
    assert cfg.logger.backend == "none"
    assert cfg.env.num_envs == 32 and cfg.asset.kind == "drawer"
    spec = cfg.train.eval_after
    assert spec.episodes == 50 and list(spec.resistances) == ["smooth", "normal", "high"]
    # off unless asked for
    assert load_config([]).train.eval_after is None


def test_sweeper_params_span_collision_resistance_and_category():
    cfg = hydra_config(["+experiment=fidelity_ablation"])
    params = cfg.hydra.sweeper.params
    parsed = OverridesParser.create().parse_overrides([f"{k}={v}" for k, v in params.items()])
    axes = {
        o.key_or_group: list(o.sweep_string_iterator()) if o.is_sweep_override() else [o.value()]
        for o in parsed
    }
    assert axes["collision"] == ["coacd", "hull"]
    assert axes["resistance"] == ["smooth", "normal", "high"]
    assert axes["asset"] == ["knob", "finger_pull", "two_point"]
    assert "env.seed" in axes and "gripper" in axes
    assert math.prod(len(v) for v in axes.values()) == 18
    assert cfg.hydra.sweep.dir.startswith("outputs/fidelity_ablation/")
    assert "JoblibLauncher" in cfg.hydra.launcher._target_ and cfg.hydra.launcher.n_jobs == 2
    # the Ray and SLURM launcher presets build on the plugins' own configs
    for name, base in (("realikea_ray", "ray"), ("realikea_slurm", "submitit_slurm")):
        preset = yaml.safe_load((CONF_DIR / "hydra" / "launcher" / f"{name}.yaml").read_text())
        assert preset["defaults"][0] == base


def test_eval_overrides_replace_the_training_resistance_and_keep_the_rest(tmp_path):
    spec = OmegaConf.create({"episodes": 5, "resistances": ["high"], "dr": "randomized", "seed": 7})
    run = ["collision=hull", "resistance=smooth", "+experiment=fidelity_ablation", "env.seed=3",
           "dr.switch_iteration=4", "train.eval_after.episodes=5", "asset=knob"]  # fmt: skip
    out = eval_overrides(run, tmp_path / "model_9.pt", "high", spec)
    assert out[:3] == ["collision=hull", "+experiment=fidelity_ablation", "asset=knob"]
    assert "resistance=smooth" not in out and "env.seed=3" not in out
    assert out[-5:] == [
        f"policy.path={(tmp_path / 'model_9.pt').resolve()}",
        "resistance=high",
        "episodes=5",
        "dr=randomized",
        "env.seed=7",
    ]
    plain = eval_overrides(run, tmp_path / "m.pt", "normal", OmegaConf.create({"episodes": 1}))
    assert "env.seed=3" in plain and "dr.switch_iteration=4" in plain
    assert "collision=hull" in plain  # unset: the run's own geometry
    faithful = OmegaConf.create({"episodes": 1, "collision": "coacd"})
    out = eval_overrides(run, tmp_path / "m.pt", "high", faithful)
    assert "collision=hull" not in out and out.count("collision=coacd") == 1


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    """`train.py -m +experiment=fidelity_ablation` with every axis pinned: one tiny run."""
    root = tmp_path_factory.mktemp("ablation")
    args = ["-m", "+experiment=fidelity_ablation", "hydra/launcher=basic", *TINY]
    args += ["collision=hull", f"paths.library={root / 'library'}", f"hydra.sweep.dir={root / 's'}"]
    out = subprocess.run(
        [sys.executable, "train.py", *args], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-3000:]
    return root / "s"


def test_tiny_run_writes_eval_json_under_three_modes(sweep):
    runs = [p for p in sweep.iterdir() if p.is_dir()]
    assert [r.name for r in runs] == ["hull_smooth_two_point_franka_hand_s0"]
    run = runs[0]
    assert (run / "metrics.csv").is_file() and (run / ".hydra" / "config.yaml").is_file()
    report = json.loads((run / "eval.json").read_text())
    assert report["checkpoint"] == "model_1.pt" and report["train_seconds"] > 0
    assert list(report["modes"]) == ["smooth", "normal", "high"]
    assert report["versions"]["mujoco"] == mujoco.__version__ and report["versions"]["torch"]
    for mode, entry in report["modes"].items():
        assert entry["episodes"] == 2
        assert entry["fail"] + entry["partial"] + entry["success"] == pytest.approx(1.0)
        assert tuple(entry["strategies"]) == STRATEGIES
        assert sum(entry["strategies"].values()) == pytest.approx(1.0)
        assert "friction_share" in entry["contacts"]
        assert entry["dr"] == "randomized" and entry["env_seed"] == 1000
        assert entry["command"].startswith("realikea eval ")
        assert f"resistance={mode}" in entry["command"]


def test_rerun_repeats_the_evaluation_of_a_finished_run(sweep, tmp_path, capsys):
    from realikea.cli import main

    source, run = sweep / "hull_smooth_two_point_franka_hand_s0", tmp_path / "run"
    shutil.copytree(source, run)
    old = json.loads((run / "eval.json").read_text())
    stale = {"checkpoint": "x", "train_seconds": old["train_seconds"], "modes": {}}
    (run / "eval.json").write_text(json.dumps(stale))  # as if from an older evaluation
    assert main(["eval", "rerun", str(run)]) == 0
    new = json.loads((run / "eval.json").read_text())
    assert new["checkpoint"] == "model_1.pt" and new["train_seconds"] == old["train_seconds"]
    assert list(new["modes"]) == ["smooth", "normal", "high"]
    for mode, entry in new["modes"].items():  # the same command gives the same episodes
        same = old["modes"][mode]["command"].replace(str(source), str(run))
        assert entry["command"] == same
        assert entry["strategies"] == old["modes"][mode]["strategies"]
        assert entry["success"] == old["modes"][mode]["success"]
    assert main(["eval", "rerun", str(tmp_path)]) == 2  # not a training run
    assert "not a training run" in capsys.readouterr().err


def test_rerun_on_another_geometry_writes_its_own_file_and_checks_every_run_first(
    sweep, tmp_path, capsys
):
    from realikea.cli import main

    run = tmp_path / "run"
    shutil.copytree(sweep / "hull_smooth_two_point_franka_hand_s0", run)
    before = (run / "eval.json").read_text()
    assert main(["eval", "rerun", "--collision", "nosuch", str(run)]) == 2
    assert "nosuch" in capsys.readouterr().err and not (run / "eval_nosuch.json").exists()
    assert main(["eval", "rerun", str(run), str(tmp_path), "--collision", "hull"]) == 2
    assert not (run / "eval_hull.json").exists()  # the second folder is no run: nothing ran
    assert main(["eval", "rerun", "--collision", "hull", str(run)]) == 0
    own = json.loads((run / "eval_hull.json").read_text())
    assert (run / "eval.json").read_text() == before
    assert own["spec"]["collision"] == "hull" and list(own["modes"]) == ["smooth", "normal", "high"]
    for entry in own["modes"].values():
        assert "collision=hull" in entry["command"] and "collision=coacd" not in entry["command"]


def fake_coacd_run(run, target):
    """A copy of the tiny run relabelled as CoACD, with pinch/hook strategies and successes
    (4 episodes a mode, so every rate below is a count of them, as in a real eval.json)."""
    shutil.copytree(run, target)
    config = target / ".hydra" / "config.yaml"
    config.write_text(config.read_text().replace("source: hull", "source: coacd"))
    report = json.loads((target / "eval.json").read_text())
    for entry in report["modes"].values():
        entry.update(episodes=4, fail=0.25, partial=0.25, success=0.5)
        entry["strategies"] = {"hook": 0.5, "lever": 0.0, "pinch": 0.25, "none": 0.25}
        entry["success_strategies"] = {"hook": 0.8, "lever": 0.0, "pinch": 0.2, "none": 0.0}
        entry["contacts"]["friction_share"] = 0.3
    (target / "eval.json").write_text(json.dumps(report))
    (target / "videos").mkdir()
    (target / "videos" / "eval_hook_success.mp4").write_bytes(b"")
    (target / "videos" / "eval_hook_success.png").write_bytes(b"")


def test_report_aggregates_runs_into_markdown_and_plots(study, sweep, tmp_path):
    root = tmp_path / "runs"
    shutil.copytree(sweep, root)
    run = root / "hull_smooth_two_point_franka_hand_s0"
    fake_coacd_run(run, root / "coacd_smooth_two_point_franka_hand_s0")
    out = tmp_path / "report"
    assert study.report.report([root], out) == out / "report.md"
    text = (out / "report.md").read_text()
    assert "2 runs from" in text
    # one seed a cell: Wilson's interval on 2 of 4 episodes, Newcombe's on the difference
    # the tiny run's training success never reached 50 %: 0 seeds learned
    assert "| coacd | smooth | two_point | 1 | 0 | 0.50 [0.15, 0.85] | 0.50 [0.15, 0.85] |" in text
    assert "| coacd | smooth | two_point | high | 0.50 | 0.00 | +0.50 [" in text
    assert "| not significant |" in text and "evaluation split test" in text
    assert "| coacd | two_point | 0.25 | 0.50 | 0.00 | 0.00 | 0.00 | 0.25 | 0.30 |" in text
    assert "## Compute" in text and "coacd_smooth_two_point_franka_hand_s0 | 2 | 2 |" in text
    # per run: success under the three modes, strategies under smooth, never 50 % in training
    per_run = "| coacd_smooth_two_point_franka_hand_s0 | 0.50 | 0.50 | 0.50 | 0.25 | 0.50 |"
    assert per_run + " 0.00 | – | – | 0.25 | 0.80 | – |" in text  # no front labels in the fake
    assert "| train S | change | train P | change |" in text  # 2 iterations: nothing before
    assert "Typical: `hook`, an episode ending in success ([MP4](" in text
    assert "eval_hook_success.mp4)" in text and "eval_hook_success.png)" in text
    for name in ("success", "outcomes", "strategies", "learning_curves"):
        assert (out / f"{name}.png").stat().st_size > 5_000


def fake_phase_map(folder, coacd_success, hull_success):
    """A phase_map.py output directory of one cell (70 N, mu 0.3) for a CoACD and a hull policy."""
    folder.mkdir()
    cell = {"category": "two_point", "cone": "elliptic", "force": 70.0, "friction": 0.3}
    cell |= {"resistance": "high", "split": "test", "episodes": 20}
    records = [
        cell
        | {
            "policy": "coacd",
            "success": coacd_success,
            "command": "realikea eval policy=checkpoint policy.path=grid/coacd_s0/model_1300.pt",
        },
        cell | {"policy": "hull", "success": hull_success},
    ]
    (folder / "cells.jsonl").write_text("\n".join(json.dumps(r) for r in records) + "\n")
    (folder / "phase_map.md").write_text("# Friction-trap phase map\n")
    (folder / "phase_map.png").write_bytes(b"")


def test_the_report_shows_each_phase_map_with_its_tested_difference(study, sweep, tmp_path):
    fake_phase_map(tmp_path / "paper_map", coacd_success=0.5, hull_success=0.05)
    out = tmp_path / "report"
    study.report.report([sweep], out, [tmp_path / "paper_map"])
    text = (out / "report.md").read_text()
    assert "## Friction-trap phase maps" in text and "### ../paper_map" in text
    assert "Policies coacd, hull; elliptic cones; 2 cells of 20 episodes, test parts" in text
    assert "![paper_map](../paper_map/phase_map.png)" in text
    assert "- coacd: `grid/coacd_s0/model_1300.pt`" in text
    # 10 of 20 against 1 of 20: Newcombe's interval excludes zero, so the cell is bold
    assert "| 70 N | **+0.45 [" in text


def test_a_phase_map_without_its_figure_or_cells_is_refused_before_anything_is_written(
    study, sweep, tmp_path
):
    fake_phase_map(tmp_path / "map", coacd_success=0.5, hull_success=0.5)
    (tmp_path / "map" / "phase_map.png").unlink()
    out = tmp_path / "report"
    with pytest.raises(RealIkeaError, match="not a phase map.*phase_map.png"):
        study.report.report([sweep], out, [tmp_path / "map"])
    (tmp_path / "map" / "phase_map.png").write_bytes(b"")
    (tmp_path / "map" / "cells.jsonl").write_text("")
    with pytest.raises(RealIkeaError, match="phase map without cells"):
        study.report.report([sweep], out, [tmp_path / "map"])
    assert not out.exists()
    # the script prints the error and exits 2
    script = WORKSPACE / "experiments/fidelity_ablation/report.py"
    args = [str(sweep), "--out", str(out), "--phase-maps", str(tmp_path / "map")]
    done = subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True)
    assert done.returncode == 2 and "error: phase map without cells" in done.stderr


def test_the_interval_table_counts_the_seeds_that_learned(study):
    its = list(range(100))
    learned = {"metrics": {"/episode/success": (its, [0.0] * 50 + [0.9] * 50)}}
    never = {"metrics": {"/episode/success": (its, [0.0] * 100)}}
    key = ("coacd", "high", "two_point")
    cells = {key: {"high": {"runs": [(45, 50), (0, 50)], "seeds": 2}}}
    lines = study.tables.interval_lines(
        cells, {key: [learned, never]}, ["coacd"], ["high"], ["two_point"], ["high"]
    )
    assert lines[-1].startswith("| coacd | high | two_point | 2 | 1 | 0.45 [")


def test_failure_modes_carry_intervals_and_the_slip_difference_is_tested(study):
    seeds = [(0, 50), (1, 50)]  # two seeds: a bootstrap over seeds and episodes
    coacd = {"runs": seeds, "failure_runs": {f: seeds for f in FAILURE_MODES}}
    slipping = [(30, 50), (40, 50)]
    hull = {"runs": seeds, "failure_runs": {**coacd["failure_runs"], "slip": slipping}}
    cells = {
        ("coacd", "high", "two_point"): {"high": coacd},
        ("hull", "high", "two_point"): {"high": hull},
    }
    args = (cells, ["coacd", "hull"], ["high"], ["two_point"])
    table = study.tables.failure_lines(*args)
    mean, lo, hi = seed_interval(slipping)
    assert table[-1].startswith(f"| hull | high | two_point | {mean:.2f} [{lo:.2f}, {hi:.2f}] |")
    slip = study.tables.difference_lines(*args, ["high"], "slip")
    assert slip[0] == "## Slip rate: CoACD − hull"
    d, lo, hi = seed_difference(seeds, slipping)
    # the bootstrap's interval excludes zero, but two seeds a side are tested at the seed
    # level: 6 splits, the observed one and its mirror as far apart, p = 2 / 6
    assert slip[-1] == (
        f"| coacd | high | two_point | high | 0.01 | 0.70 | {d:+.2f} [{lo:+.2f}, {hi:+.2f}] "
        "| not significant (seeds: p = 0.33) |"
    )
    assert hi < 0
    # success differs by nothing: the same table of success says so
    same = study.tables.difference_lines(*args, ["high"])
    assert same[-1].endswith("| not significant (seeds: p = 1.00) |")


def test_strategy_shares_are_counted_per_seed_and_the_hook_difference_is_tested(study):
    def run(collision, hook):
        entry = {"fail": 0.0, "partial": 0.0, "success": 1.0, "episodes": 50,
                 "strategies": {"hook": hook, "pinch": 1.0 - hook}}  # fmt: skip
        return {"collision": collision, "gripper": "franka_hand", "contact": "elliptic",
                "iterations": 1500, "switch": 900, "resistance": "high",
                "category": "two_point", "eval": {"modes": {"high": entry}}}  # fmt: skip

    cells, _ = study.cells.aggregate([run("coacd", 0.36), run("hull", 0.02)])
    coacd = cells["coacd", "high", "two_point"]["high"]
    assert coacd["strategy_runs"]["hook"] == [(18, 50)] and coacd["strategies"]["hook"] == 0.36
    args = (cells, ["coacd", "hull"], ["high"], ["two_point"], ["high"])
    hook = study.tables.difference_lines(*args, "hook")
    assert hook[0] == "## Hook rate: CoACD − hull"
    lo, hi = diff_interval(18, 50, 1, 50)  # one seed a side: Newcombe's interval
    assert hook[-1] == (
        f"| coacd | high | two_point | high | 0.36 | 0.02 | +0.34 [{lo:+.2f}, {hi:+.2f}] "
        "| significant |"
    )


def test_form_closure_adds_hooks_and_levers_per_seed_before_the_difference(study):
    def run(collision, hook, lever):
        shares = {"hook": hook, "lever": lever, "pinch": 1.0 - hook - lever}
        entry = {"fail": 0.0, "partial": 0.0, "success": 1.0, "episodes": 50, "strategies": shares}
        return {"collision": collision, "gripper": "franka_hand", "contact": "elliptic",
                "iterations": 900, "switch": 300, "resistance": "normal",
                "category": "knob", "eval": {"modes": {"high": entry}}}  # fmt: skip

    runs = [run("coacd", 0.0, 0.56), run("hull", 0.04, 0.10)]
    cells, _ = study.cells.aggregate(runs)
    hull = cells["hull", "normal", "knob"]["high"]
    assert study.cells.measured_runs(hull, "form closure") == [(7, 50)]
    args = (cells, ["coacd", "hull"], ["normal"], ["knob"], ["high"])
    closure = study.tables.difference_lines(*args, "form closure")
    assert closure[0] == "## Form closure rate: CoACD − hull"
    lo, hi = diff_interval(28, 50, 7, 50)
    assert closure[-1] == (
        f"| coacd | normal | knob | high | 0.56 | 0.14 | +0.42 [{lo:+.2f}, {hi:+.2f}] "
        "| significant |"
    )
    # a cell evaluated before strategy labels existed has no form-closure rate
    assert study.cells.measured_runs({"runs": [(50, 50)]}, "form closure") is None


def test_videos_are_recorded_once_from_the_checkpoint_kept_with_the_run(
    study, tmp_path, monkeypatch
):
    run_dir = tmp_path / "hull_high_two_point_s0"
    run_dir.mkdir()
    (run_dir / "model_899.pt").write_bytes(b"")
    trained_at = "policy.path=/gone/outputs/hull_high_two_point_s0/model_899.pt"
    command = f"realikea eval asset=two_point {trained_at} resistance=high episodes=50"
    run = {
        "dir": run_dir,
        "resistance": "high",
        "eval": {"checkpoint": "model_899.pt", "modes": {"high": {"command": command}}},
        "strips": [],
    }
    recorded = {**run, "dir": tmp_path / "recorded", "strips": [tmp_path / "eval_hook_success.png"]}
    calls = []
    monkeypatch.setattr(
        study.videos, "evaluate_and_record", lambda overrides, stem: calls.append(overrides)
    )
    study.videos.record_videos([recorded, run], episodes=8)
    (overrides,) = calls  # the run with strips already is not recorded again
    assert f"policy.path={(run_dir / 'model_899.pt').resolve()}" in overrides
    assert trained_at not in overrides and "episodes=50" not in overrides
    assert overrides[:2] == ["asset=two_point", "resistance=high"] and "episodes=8" in overrides
    with pytest.raises(RealIkeaError, match="not a `realikea eval` command"):
        command_overrides("python eval.py asset=two_point")


def test_the_papers_schedule_is_its_own_variant_beside_the_grids(study):
    def run(collision, iterations, switch):
        return {"collision": collision, "gripper": "franka_hand", "contact": "elliptic",
                "iterations": iterations, "switch": switch}  # fmt: skip

    grid, paper = run("coacd", 900, 300), run("hull", 1500, 900)
    assert study.cells.variant(grid, presets=1) == "coacd"  # one schedule: no tag
    assert study.cells.variant(grid, 1, schedules=2) == "coacd (900 its, switch 300)"
    assert study.cells.variant(paper, 1, 2) == "hull (1500 its, switch 900)"
    assert study.cells.variant(paper, 2, 2) == (
        "hull (franka_hand, elliptic; 1500 its, switch 900)"
    )
    assert schedule(run("coacd", 500, None)) == "500 its"  # fixed poses
    # the switch is read from the run's dr: only a two-phase schedule has one
    assert two_phase_switch({"mode": "two_phase", "switch_iteration": 900}) == 900
    assert two_phase_switch({"mode": "randomized", "switch_iteration": 900}) is None
    assert two_phase_switch(None) is None  # a config without dr


def test_the_curves_average_a_trailing_window_of_iterations():
    its, means = trailing_mean([2, 0, 1, 3], [1.0, 0.0, 0.0, 1.0], window=2)
    assert its.tolist() == [1, 2, 3] and means.tolist() == [0.0, 0.5, 1.0]  # sorted by iteration
    its, means = trailing_mean([0], [1.0], window=2)
    assert len(its) == len(means) == 0  # no full window yet


def test_iterations_to_success_is_the_first_window_reaching_the_level():
    its = list(range(100))
    values = [0.0] * 40 + [1.0] * 60
    run = {"metrics": {"/episode/success": (its, values)}}
    # the 20 iterations from 35 hold 15 successes (0.75), those from 34 only 14
    assert iterations_to_success(run, level=0.75, window=20) == 35
    assert iterations_to_success(run, level=1.0, window=20) == 40
    never = {"metrics": {"/episode/success": (its, [0.4] * 100)}}
    assert iterations_to_success(never) is None
    assert iterations_to_success({"metrics": {}}) is None


def test_a_last_partial_window_crossing_the_level_does_not_count_as_learned():
    # 400 iterations, success 0.52 over the last 19: the best full window of 20 (from 380)
    # averages 0.494; the window from 381, cut off by the end of the run, 0.52
    its = list(range(400))
    values = [0.0] * 381 + [0.52] * 19
    run = {"metrics": {"/episode/success": (its, values)}}
    assert iterations_to_success(run) is None
    # one more iteration completes the window from 381, which then counts
    longer = {"metrics": {"/episode/success": (its + [400], values + [0.52])}}
    assert iterations_to_success(longer) == 381


def test_the_trailing_mean_of_half_successes_is_exactly_one_half():
    # these 20 sum to 10; weighted by 0.05 each they summed to 0.49999999999999994
    values = [0, 0.5, 1, 1, 0, 0.25, 0.75, 0, 0.5, 1]
    values += [0.75, 0, 0.25, 0, 0.5, 1, 0.75, 0.75, 0.75, 0.25]
    _, means = trailing_mean(range(20), values, window=20)
    assert means.tolist() == [0.5]


def test_the_plateau_check_compares_the_last_window_with_the_one_before():
    its = list(range(300))
    climbing = {"metrics": {"/episode/success": (its, [0.0] * 100 + [0.2] * 100 + [0.5] * 100)}}
    mean, change = last_windows(climbing, "/episode/success", window=100)
    assert mean == pytest.approx(0.5) and change == pytest.approx(0.3)  # still climbing
    flat = {"metrics": {"/episode/success": (its, [0.9] * 300)}}
    assert last_windows(flat, "/episode/success") == pytest.approx((0.9, 0.0))
    short = {"metrics": {"/episode/success": ([0, 1], [0.0, 1.0])}}
    assert last_windows(short, "/episode/success") == (0.5, None)  # no before
    assert last_windows({"metrics": {}}, "/episode/partial") == (None, None)


@pytest.mark.slow
@pytest.mark.ray
def test_ray_launcher_runs_the_experiment_on_a_local_ray_instance(tmp_path):
    """Opt-in (`pip install -e '.[cluster]'`, `pytest -m ray`): two runs as Ray tasks."""
    pytest.importorskip("ray")
    pytest.importorskip("hydra_plugins.hydra_ray_launcher")
    args = ["-m", "+experiment=fidelity_ablation", "hydra/launcher=realikea_ray", *TINY]
    args += ["hydra.launcher.ray.init.num_cpus=2", "hydra.launcher.ray.remote.num_cpus=1"]
    args += [
        "collision=coacd,hull",
        "agent.max_iterations=1",
        "train.eval_after.resistances=[high]",
    ]
    args += [f"paths.library={tmp_path / 'library'}", f"hydra.sweep.dir={tmp_path / 's'}"]
    out = subprocess.run(
        [sys.executable, "train.py", *args], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-3000:]
    for collision in ("coacd", "hull"):
        report = json.loads(
            (
                tmp_path / "s" / f"{collision}_smooth_two_point_franka_hand_s0" / "eval.json"
            ).read_text()
        )
        assert list(report["modes"]) == ["high"] and report["modes"]["high"]["episodes"] == 2


def test_compute_counts_a_resumed_runs_iterations_and_every_launchs_wall_time(study, tmp_path):
    assert _trained_iterations({"checkpoint": "model_899.pt"}, 301) == 900
    assert _trained_iterations({}, 301) == 301  # no checkpoint named
    resumed = {"dir": tmp_path / "resumed", "iterations": 900, "launch_iterations": 301,
               "num_envs": 64, "eval": {"train_seconds": 602.0, "eval_seconds": 120.0},
               "wall": [3000.0, 1800.0]}  # fmt: skip
    lines = study.tables.compute_lines([resumed], tmp_path)
    (row,) = [x for x in lines if x.startswith("| resumed |")]
    assert row == "| resumed | 900 | 64 | 301 | 10.0 | 2.00 | 2.0 | 80.0 |"
    assert lines[-1] == "Total compute (sum over runs; wall time where recorded): 1.33 h."
