"""The `appendix` reward variant: the paper's four stages, latched (a stage, once reached, is never
left); constants in `AppendixParams`. A checkpoint whose config names no
reward variant was trained on it.

Stage 1 approaches a pre-grasp target t1 with the jaws open, stage 2 refines towards t2,
stage 3 closes the jaws, stage 4 rewards opening. Each stage adds the maximum of the ones
before it (M1, M2, beta), so the reward never drops when a stage is reached.

Its traps (the `gated` variant removes each; the runs that fell into them:
`experiments/reward_screen/README.md`): closed empty jaws within tau2 of t2 reach stage 4, which
pays M1 + M2 + beta a step with nothing opened; the 2 -> 3 gate is a 2 cm ball around a point
6 mm inside the handle's surface; and kappa log(100 q + 1) pays more for the first 2 cm than for
10 -> 20 cm, with no bonus at success.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from realikea.rewards.terms import (
    StageParams,
    StepValues,
    approach,
    ik_failure_term,
    jerk_term,
)


@dataclass(frozen=True)
class AppendixParams(StageParams):
    """The paper's appendix constants (stages, weights) plus the auxiliary cost weights:
    `task/reward=appendix` is built from these."""

    kappa: float = 15.0  # stage 4: kappa log(100 q + 1)
    tau2: float = 0.02  # m: stage 3 within this of t2, stage 4 once the jaws close there


def open_reward(q: float, kappa: float) -> float:
    """kappa * log(100 q + 1): steep at q = 0 to reward breaking static friction."""
    return kappa * math.log(100.0 * max(q, 0.0) + 1.0)


def staged_reward(stage: int, d1: float, d2: float, aperture: float, q: float, p: AppendixParams):
    """The reward of the active stage (1-4)."""
    if stage == 1:
        s_open = 1.0 if aperture > p.open_above else 0.0
        return p.w_open1 * s_open + approach(d1, p.w_app1, p.eps)
    if stage == 2:
        s_open = 1.0 if aperture > p.open_above else 0.0
        return p.m1 + p.w_open2 * s_open + approach(d2, p.w_app2, p.eps)
    if stage == 3:
        s_close = 1.0 if aperture < p.close_below else 0.0
        return p.m1 + p.m2 + p.beta * s_close
    return open_reward(q, p.kappa) + p.m1 + p.m2 + p.beta


def latched_stage(stage: int, d1: float, d2: float, aperture: float, p: AppendixParams) -> int:
    """Latched stage progress: 1 -> 2 within tau1 of t1, 2 -> 3 within tau2 of t2,
    3 -> 4 once the jaws are closed there (grasp readiness); a stage is never left."""
    if stage == 1 and d1 < p.tau1:
        stage = 2
    if stage == 2 and d2 < p.tau2:
        stage = 3
    if stage == 3 and aperture < p.close_below and d2 < p.tau2:
        stage = 4
    return stage


def next_stage(stage: int, v: StepValues, p: AppendixParams) -> int:
    """The stage after a step that started in `stage` (`latched_stage`)."""
    return latched_stage(stage, v.d1, v.d2, v.aperture, p)


def stage_term(v: StepValues, p: AppendixParams) -> float:
    """The active stage's reward (its own weights are the appendix's constants)."""
    return staged_reward(v.stage, v.d1, v.d2, v.aperture, v.opening, p)


# name -> (term, the params field that weighs it; None: the term carries its own weights)
TERMS = {
    "stage": (stage_term, None),
    "jerk": (jerk_term, "w_jerk"),
    "ik_failure": (ik_failure_term, "ik_cost"),
}
