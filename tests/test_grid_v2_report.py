"""The fidelity grid v2's report (experiments/fidelity_ablation/grid_v2_report.py) on made-up
kept runs whose answers are known by hand: the registered comparisons, Holm over all four,
the stratified test, and the sensitivity analysis without dead runs."""

from __future__ import annotations

import csv
import json

import pytest
from omegaconf import OmegaConf

from realikea.files import WORKSPACE
from realikea.sim.resistance import MODES
from realikea.tasks.contacts import STRATEGIES

TEMPLATE = WORKSPACE / "experiments/fidelity_ablation/results/grid/coacd_high_two_point_s0"


@pytest.fixture
def report(load_script, monkeypatch, tmp_path):
    module = load_script("experiments/fidelity_ablation/grid_v2_report.py")
    monkeypatch.setattr(module, "KEPT", tmp_path)
    monkeypatch.setattr(module, "PHASE_RESULTS", tmp_path / "phase_map" / "cells.jsonl")
    return module


def make_run(root, collision, resistance, category, seed, success, hook=0.0, learned=True):
    """A kept run: the template's config relabelled, a metrics.csv whose success is 1 (learned)
    or 0 throughout 40 iterations, and an eval.json with `success` in every mode, `hook` of
    the successes hooked and the rest pinched."""
    run = root / f"{collision}_{resistance}_{category}_s{seed}"
    (run / ".hydra").mkdir(parents=True)
    cfg = OmegaConf.load(TEMPLATE / ".hydra" / "config.yaml")
    cfg.collision.source, cfg.resistance.name, cfg.asset.category = collision, resistance, category
    cfg.env.seed, cfg.agent.max_iterations = seed, 40
    OmegaConf.save(cfg, run / ".hydra" / "config.yaml")
    rows = ["iteration,tag,value"] + [f"{i},/episode/success,{float(learned)}" for i in range(40)]
    (run / "metrics.csv").write_text("\n".join(rows) + "\n")
    shares = dict.fromkeys(STRATEGIES, 0.0) | ({"hook": hook, "pinch": 1 - hook} if success else {})
    mode = {"episodes": 50, "success": success, "success_strategies": shares}
    report = {"checkpoint": "model_39.pt", "modes": dict.fromkeys(MODES, mode)}
    (run / "eval.json").write_text(json.dumps(report))
    (run / "wall.json").write_text(json.dumps({"launches_seconds": [1800.0, 600.0]}))
    return run


def test_registered_comparisons_by_hand(report, tmp_path):
    for seed, hook in zip(range(100, 105), (0.9, 0.8, 0.85, 0.7, 0.95), strict=True):
        make_run(tmp_path, "coacd", "high", "two_point", seed, 0.8, hook)
    for seed, hook in zip(range(100, 105), (0.2, 0.3, 0.1, 0.4, 0.25), strict=True):
        make_run(tmp_path, "hull", "high", "two_point", seed, 0.8, hook)
    make_run(tmp_path, "hull", "high", "two_point", 105, 0.0, learned=False)  # a dead run
    assert report.main([]) == 0
    results = json.loads((tmp_path / "comparisons.json").read_text())
    first, *rest = results["registered"]
    # the dead hull run counts 0: hull mean 0.25 * 5 / 6
    assert first["difference"] == pytest.approx(0.84 - 1.25 / 6)
    # one of C(11, 5) assignments is as extreme (sizes differ: the mirror image is not)
    assert first["values"][0][1][-1] == 0.0 and first["p"] == pytest.approx(1 / 462)
    # Holm over the registered four: the three not yet computable count as p = 1
    assert first["p_holm"] == pytest.approx(4 / 462) and first["significant"]
    assert [r["difference"] for r in rest] == [None, None, None]
    without = results["sensitivity_learned_only"][0]
    assert without["p"] == pytest.approx(2 / 252)
    assert without["difference"] == pytest.approx(0.84 - 0.25)
    rows = list(csv.DictReader((tmp_path / "runs.csv").open()))
    assert len(rows) == 11 and sum(r["learned_at"] == "" for r in rows) == 1
    text = (tmp_path / "report.md").read_text()
    assert "11 of 66 planned runs kept; 10 learned." in text
    assert "Compute: 7.3 h of wall time over the launches of 11 kept runs" in text
    assert rows[0]["wall_minutes"] == "40.0"
    assert "| two_point | high | hull | 6 / 5 | 5 |" in text and "not computable yet" in text
    # the phase map has not run: comparison 4 has 11 kept policies without a value
    assert "| 0 / 0 (11 kept, not yet evaluated) | not computable yet |" in text
    # each policy's episodes: 0.9 of its 40 successes hooked; the dead run has no successes
    assert "| 1 | `coacd_high_two_point_s100` | 0.90 | 36 / 40 | [0.77, 0.96] |" in text
    assert "| 1 | `hull_high_two_point_s105` | 0.00 | 0 / 0 | – |" in text
    assert "| 4 | `hull_high_two_point_s105` | not yet evaluated | | |" in text


def test_smooth_policies_in_high_are_compared_within_each_category(report, tmp_path):
    levels = {"two_point": 0.9, "knob": 0.5, "finger_pull": 0.1}  # categories far apart
    for category, level in levels.items():
        for seed in (100, 101):
            make_run(tmp_path, "coacd", "smooth", category, seed, level + 0.02 * (seed - 99))
            make_run(tmp_path, "hull", "smooth", category, seed, level - 0.02 * (seed - 99))
    assert report.main([]) == 0
    third = json.loads((tmp_path / "comparisons.json").read_text())["registered"][2]
    assert [len(a) for a, _ in third["values"]] == [2, 2, 2]
    assert third["difference"] == pytest.approx(0.06)
    # within-category permutations only: 6 ** 3 assignments, two as extreme as observed
    assert third["p"] == pytest.approx(2 / 216)
    assert third["low"] is not None and 0 < third["low"] < 0.06 < third["high"]
    text = (tmp_path / "report.md").read_text()
    assert "| 3. trained in smooth" in text and "[+0.0" in text


def test_an_interval_no_shift_bounds_is_written_as_infinite(report, tmp_path):
    for collision, hook in (("coacd", 0.9), ("hull", 0.1)):
        for seed in (100, 101, 102):
            make_run(tmp_path, collision, "high", "two_point", seed, 0.8, hook)
    assert report.main([]) == 0
    first = json.loads((tmp_path / "comparisons.json").read_text())["registered"][0]
    assert first["p"] == pytest.approx(0.1) and (first["low"], first["high"]) == (None, None)
    assert (
        "+0.80 [−∞, ∞] | 0.1000 | 0.4000 | not significant |"
        in (tmp_path / "report.md").read_text()
    )


def test_the_extra_evaluations_pick_hull_runs_and_the_two_point_high_policies(
    load_script, monkeypatch, tmp_path
):
    evals = load_script("experiments/fidelity_ablation/grid_v2_eval.py")
    monkeypatch.setattr(evals, "KEPT", tmp_path)
    for name in ("coacd_high_two_point_s100", "hull_high_two_point_s100", "hull_high_knob_s100"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "eval.json").write_text("{}")
        (tmp_path / name / "model_599.pt").write_bytes(b"")
    (tmp_path / "hull_high_knob_s101").mkdir()  # still training: no eval.json
    (tmp_path / "hull_high_knob_s100" / "eval_hull.json").write_text("{}")  # already done
    runs = evals.kept_runs()
    assert [r.name for r in evals.own_geometry_todo(runs)] == ["hull_high_two_point_s100"]
    assert evals.phase_policies(runs) == [
        f"{name}={tmp_path / name / 'model_599.pt'}"
        for name in ("coacd_high_two_point_s100", "hull_high_two_point_s100")
    ]


def test_the_frames_are_chosen_by_rule_one_per_cell(report, tmp_path):
    def strip(run, label):
        (run / "videos").mkdir(exist_ok=True)
        (run / "videos" / f"eval_{label}_success.png").write_bytes(b"png")

    for seed in (100, 101):
        strip(make_run(tmp_path, "coacd", "high", "two_point", seed, 0.8, 1.0), "hook")
    hull = [make_run(tmp_path, "hull", "high", "two_point", s, 0.8, 0.5) for s in (100, 101)]
    strip(hull[1], "hook")  # only the second hull seed recorded a hook
    strip(hull[0], "pinch")
    strip(make_run(tmp_path, "hull", "smooth", "knob", 100, 0.8), "pinch")
    assert report.main([]) == 0
    text = (tmp_path / "report.md").read_text().split("## Frames")[1]
    two_point, hooks, levers, pinches = text.split("### ")[1:]
    shown = "![{0} {1}]({0}/videos/eval_{1}_success.png)"
    assert shown.format("coacd_high_two_point_s100", "hook") in two_point
    assert "coacd, `pinch`: no recorded success." in two_point
    assert shown.format("hull_high_two_point_s101", "hook") in two_point
    assert shown.format("hull_high_two_point_s100", "pinch") in two_point
    # one strip per cell: the second CoACD seed's hook repeats the first's cell
    assert hooks.count("![") == 2 and "coacd_high_two_point_s101" not in hooks
    assert levers.startswith("`lever`: 0 successes") and "![" not in levers
    assert pinches.count("![") == 2 and shown.format("hull_smooth_knob_s100", "pinch") in pinches
