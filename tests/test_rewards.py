"""The appendix reward variant's formulas: saturation values, continuity and monotonicity across
stages, latched progress."""

from __future__ import annotations

import numpy as np
import pytest

from realikea.rewards.appendix import (
    AppendixParams,
    latched_stage,
    open_reward,
    staged_reward,
)
from realikea.rewards.terms import jerk_penalty
from realikea.tasks.outcome import fractions, outcome

P = AppendixParams(w_open2=0.0)  # the paper's constants
OUTCOME = {"success": {"slide": 0.20, "hinge": 0.785}, "partial": {"slide": 0.02, "hinge": 0.087}}


def test_saturation_levels_match_the_appendix():
    assert P.m1 == pytest.approx(2 + 2 * np.log(100))
    assert P.m2 == pytest.approx(2 * np.log(100))
    # stage 1 reaches M1 at d1 = 0 with the jaws open; stage 2 reaches M1 + M2 at d2 = 0
    assert staged_reward(1, 0.0, 1.0, 1.0, 0.0, P) == pytest.approx(P.m1)
    assert staged_reward(2, 1.0, 0.0, 1.0, 0.0, P) == pytest.approx(P.m1 + P.m2)
    assert staged_reward(3, 0, 0, 0.0, 0.0, P) == pytest.approx(P.m1 + P.m2 + P.beta)
    assert staged_reward(4, 0, 0, 0.0, 0.0, P) == pytest.approx(P.m1 + P.m2 + P.beta)


def test_open_reward_formula():
    assert open_reward(0.0, 15) == 0.0
    assert open_reward(0.2, 15) == pytest.approx(15 * np.log(21))
    assert open_reward(-0.01, 15) == 0.0  # a front pushed shut earns nothing, never negative
    slope = np.diff([open_reward(q, 15) for q in np.linspace(0, 0.5, 200)])
    assert np.all(slope > 0) and np.all(np.diff(slope) < 0)  # increasing, diminishing


@pytest.mark.parametrize("d", [0.0, 0.01, 0.1, 0.5, 0.98])
def test_each_stage_starts_at_or_above_the_previous_ones_maximum(d):
    apertures = np.linspace(0, 1, 11)
    best = {s: max(staged_reward(s, 0, 0, w, 0, P) for w in apertures) for s in (1, 2, 3)}
    assert staged_reward(2, 1.0, d, 0.5, 0, P) >= best[1] - 1e-9
    assert staged_reward(3, 1.0, 1.0, 0.5, 0, P) >= best[2] - 1e-9
    assert staged_reward(4, 1.0, 1.0, 0.5, 0.0, P) >= best[3] - 1e-9


def test_reward_is_continuous_at_the_stage_boundaries_it_is_reached_from():
    """Stage 2 starts where stage 1's open-jaw approach saturates; stage 4 where stage 3 ends."""
    start_of_2 = staged_reward(2, 0.0, 0.99, 1.0, 0, P)
    assert start_of_2 == pytest.approx(P.m1 - P.w_app2 * np.log(1.0), abs=0.05)
    assert staged_reward(4, 0, 0, 0.0, 1e-9, P) == pytest.approx(
        staged_reward(3, 0, 0, 0.0, 0, P), abs=1e-5
    )


@pytest.mark.parametrize(
    ("stage", "d1", "d2", "aperture", "expected"),
    [
        (1, 0.04, 0.3, 1.0, 2),  # within tau1 of t1
        (1, 0.2, 0.3, 1.0, 1),
        (2, 0.2, 0.01, 1.0, 3),  # within tau2 of t2
        (3, 0.2, 0.01, 1.0, 3),  # jaws still open
        (3, 0.01, 0.01, 0.1, 4),  # closed there
        (4, 0.5, 0.5, 1.0, 4),  # never left
        (1, 0.0, 0.0, 0.0, 4),  # 1 -> 4 in one step when every condition holds at once
    ],
)
def test_stage_progression_is_latched_and_gated_on_closure(stage, d1, d2, aperture, expected):
    assert latched_stage(stage, d1, d2, aperture, P) == expected


def test_stage_rewards_are_plain_floats_rising_with_the_stage():
    r = [staged_reward(stage, 0.1, 0.1, 0.5, 0.1, P) for stage in (1, 2, 3, 4)]
    assert all(type(x) is float for x in r) and np.all(np.diff(r) > 0)


def test_jerk_penalty():
    a = [1.0, 0.0, 0.0, 0.0, 0.0]
    assert jerk_penalty(a, a, a, 0.1) == 0.0
    assert jerk_penalty(a, [0.0] * 5, a, 0.1) == pytest.approx(-0.1 * 4)
    assert jerk_penalty([0.0, 1.0, 0, 0, 0], [0.0] * 5, [0.0, -1.0, 0, 0, 0], 0.1) == 0.0


def test_outcome_thresholds():
    labels = outcome(
        [0.0, 0.05, 0.25, 0.05, 1.0], ["slide", "slide", "slide", "hinge", "hinge"], OUTCOME
    )
    assert labels.tolist() == ["fail", "partial", "success", "fail", "success"]
    assert fractions(labels) == {"fail": 0.4, "partial": 0.2, "success": 0.4}
