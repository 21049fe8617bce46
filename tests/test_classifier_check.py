"""The confusion-matrix counting of experiments/fidelity_ablation/classifier_check.py (no
simulation)."""

from __future__ import annotations

import pytest

from realikea.tasks.contacts import STRATEGIES


@pytest.fixture
def check(load_script):
    return load_script("experiments/fidelity_ablation/classifier_check.py")


def _record(built: str, label: str, outcome: str = "success", **extra) -> dict:
    return {"built": built, "label": label, "outcome": outcome, "category": "knob", **extra}


def test_built_strategy_follows_the_oracle_catch(check):
    assert check.built_strategy("hook_oracle", "two_point") == "hook"
    assert check.built_strategy("hook_oracle", "finger_pull") == "hook"
    assert check.built_strategy("hook_oracle", "knob") == "lever"
    for policy in ("heuristic_pull", "grasp_sampler"):
        assert {check.built_strategy(policy, c) for c in check.CATEGORIES} == {"pinch"}


def test_confusion_counts_rows_built_columns_labels(check):
    records = [
        _record("hook", "hook"),
        _record("hook", "hook"),
        _record("hook", "pinch"),
        _record("hook", "front_pinch", "partial"),
        _record("lever", "lever"),
        _record("lever", "none", "fail", note="no catch: a plain cylinder"),  # left out
        _record("pinch", "pinch"),
        _record("pinch", "none", "fail"),
    ]
    m = check.confusion(records)
    assert set(m) == set(check.BUILT)
    assert all(list(row) == list(STRATEGIES) for row in m.values())
    assert m["hook"] == {**dict.fromkeys(STRATEGIES, 0), "hook": 2, "pinch": 1, "front_pinch": 1}
    assert m["lever"]["lever"] == 1 and sum(m["lever"].values()) == 1
    assert m["pinch"] == {**dict.fromkeys(STRATEGIES, 0), "pinch": 1, "none": 1}
    assert check.as_built(m) == (4, 7)
    assert check.as_built(m, ("hook", "lever")) == (3, 5)

    won = check.confusion(records, check.SUBSETS["success"])
    assert check.as_built(won) == (4, 5) and won["hook"]["front_pinch"] == 0
    labelled = check.confusion(records, check.SUBSETS["labelled"])
    assert check.as_built(labelled, ("pinch",)) == (1, 1)
    assert labelled["hook"]["front_pinch"] == 1


def test_counts_pool_categories_and_give_wilson_shares(check):
    records = [_record("pinch", "pinch", category=c) for c in check.CATEGORIES]
    records.append(_record("pinch", "front_pinch", category="two_point"))
    out = check.counts(records)
    assert out["success/two_point"]["matrix"]["pinch"]["front_pinch"] == 1
    pooled = out["success/pooled"]["kinds"]
    assert pooled["pinch"]["as_built"] == 3 and pooled["pinch"]["n"] == 4
    low, high = pooled["pinch"]["wilson95"]
    assert low < 0.75 < high
    assert pooled["form closure"]["n"] == 0 and pooled["form closure"]["share"] is None
