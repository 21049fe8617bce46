"""The synthetic-parts pilot's driver (experiments/generalist/synthetic_pilot.py): its runs are
the registered arms, its reads cover every validation part and the trained ones, and the go rule
passes only when every seed and mode gains enough at little cost."""

from __future__ import annotations

import pytest

from realikea.assets.library import training_draw
from realikea.assets.split import main_dimension
from realikea.config import load_config


@pytest.fixture
def pilot(load_script):
    return load_script("experiments/generalist/synthetic_pilot.py")


def test_the_arms_differ_only_by_the_synthetic_parts(pilot):
    runs = {run.name: set(run.overrides) for run in pilot.runs()}
    assert sorted(runs) == ["synthetic_s30", "synthetic_s31", "withheld_s30", "withheld_s31"]
    for seed in pilot.SEEDS:
        assert runs[f"synthetic_s{seed}"] - runs[f"withheld_s{seed}"] == {pilot.SYNTHETIC}
        assert pilot.WITHHOLD in runs[f"withheld_s{seed}"]


def test_the_withheld_parts_are_each_two_point_family_s_smallest_train_part(pilot):
    cfg = load_config([*pilot.CELL, "asset.split=train"])
    parts = {c.part.id: c.part for group in training_draw(cfg, 64).groups.values() for c in group}
    smallest = {}
    for part in sorted(parts.values(), key=main_dimension):
        smallest.setdefault(part.family, part.id)
    assert set(pilot.VALIDATION_PARTS) == set(smallest.values())


def test_every_validation_part_and_the_trained_parts_are_read_in_each_mode(pilot):
    reads = {(what, mode) for what, mode, _, _ in pilot.reads()}
    assert reads == {(w, m) for w in (*pilot.VALIDATION_PARTS, "trained") for m in pilot.MODES}
    episodes = sum(n for what, mode, _, n in pilot.reads() if what != "trained" and mode == "high")
    assert episodes == 50


def rates(validation: float, trained: float) -> dict:
    return {(what, mode): value for mode in ("normal", "high")
            for what, value in (("validation", validation), ("trained", trained))}  # fmt: skip


@pytest.mark.parametrize(
    "b_validation, b_trained, verdict",
    [(0.70, 0.90, "go: yes"), (0.68, 0.90, "go: no"), (0.80, 0.84, "go: no")],
)
def test_the_go_rule_needs_the_gain_on_every_seed_and_mode_within_the_cost(
    pilot, b_validation, b_trained, verdict
):
    read = {}
    for seed in pilot.SEEDS:
        read[f"withheld_s{seed}"] = rates(0.60, 0.90)
        read[f"synthetic_s{seed}"] = rates(b_validation, b_trained)
    assert f"**{verdict}**" in pilot.report(read)
