"""The task's reward as named terms: the paper's four gated stages with monotone baselines, plus
jerk and IK-failure costs. The reward of a control step is the weighted sum of `REWARD_TERMS` in
their order (weights: `realikea/conf/task/open.yaml` reward); the task logs each term's episode sum.

Stage 1 approaches a pre-grasp target t1 with the jaws open, stage 2 refines towards t2,
stage 3 closes the jaws, stage 4 rewards opening. Each stage adds the maximum of the ones
before it (M1, M2, beta), so the reward never drops when a stage is reached.

All functions take and return plain Python numbers for one environment: the task evaluates them
once per env and control step, where numpy's per-call overhead on scalars would cost more than
the arithmetic.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property


@dataclass(frozen=True)
class RewardParams:
    """The paper's appendix constants (stages, weights) plus the auxiliary cost weights."""

    eps: float = 0.01
    w_open1: float = 2.0
    w_app1: float = 2.0
    w_open2: float = 0.0
    w_app2: float = 2.0
    beta: float = 10.0
    kappa: float = 15.0
    tau1: float = 0.05
    tau2: float = 0.02
    open_above: float = 0.6
    close_below: float = 0.4
    w_jerk: float = 0.05
    ik_cost: float = 1.0

    @cached_property
    def m1(self) -> float:
        """Saturation of stage 1: open bonus plus the approach term at d1 = 0."""
        return self.w_open1 + self.w_app1 * math.log(1.0 / self.eps)

    @cached_property
    def m2(self) -> float:
        """Saturation of stage 2: approach term at d2 = 0 (no open bonus)."""
        return self.w_open2 + self.w_app2 * math.log(1.0 / self.eps)


def approach(d: float, weight: float, eps: float) -> float:
    """The logarithmic approach shaping w * (-log(d + eps))."""
    return weight * -math.log(d + eps)


def open_reward(q: float, kappa: float) -> float:
    """kappa * log(100 q + 1): steep at q = 0 to reward breaking static friction."""
    return kappa * math.log(100.0 * max(q, 0.0) + 1.0)


def staged_reward(stage: int, d1: float, d2: float, aperture: float, q: float, p: RewardParams):
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


def next_stage(stage: int, d1: float, d2: float, aperture: float, p: RewardParams) -> int:
    """Latched stage progress: 1 -> 2 within tau1 of t1, 2 -> 3 within tau2 of t2,
    3 -> 4 once the jaws are closed there (grasp readiness); a stage is never left."""
    if stage == 1 and d1 < p.tau1:
        stage = 2
    if stage == 2 and d2 < p.tau2:
        stage = 3
    if stage == 3 and aperture < p.close_below and d2 < p.tau2:
        stage = 4
    return stage


def jerk_penalty(action, previous, before_previous, weight: float) -> float:
    """-w * ||a_t - 2 a_{t-1} + a_{t-2}||^2 (sequences of floats): discourages jerky commands."""
    total = 0.0
    for a, b, c in zip(action, previous, before_previous, strict=True):
        second_difference = a - 2.0 * b + c
        total += second_difference * second_difference
    return -weight * total


@dataclass(frozen=True)
class StepValues:
    """What the reward terms read after one control step (plain Python numbers)."""

    stage: int
    d1: float  # TCP to the pre-grasp target t1 (m)
    d2: float  # TCP to the grasp target t2 (m)
    aperture: float  # normalized finger opening
    opening: float  # the front's displacement (m or rad)
    action: list[float]
    prev_action: list[float]
    prev_prev_action: list[float]
    ik_ok: bool


def stage_term(v: StepValues, p: RewardParams) -> float:
    """The active stage's reward (its own weights are the appendix's constants)."""
    return staged_reward(v.stage, v.d1, v.d2, v.aperture, v.opening, p)


def jerk_term(v: StepValues, p: RewardParams) -> float:
    """-||a_t - 2 a_{t-1} + a_{t-2}||^2, before its weight."""
    return jerk_penalty(v.action, v.prev_action, v.prev_prev_action, 1.0)


def ik_failure_term(v: StepValues, p: RewardParams) -> float:
    """-1 on a step whose IK target was infeasible, before its weight."""
    return 0.0 if v.ik_ok else -1.0


# name -> (term, the RewardParams field that weighs it; None: the term carries its own weights)
REWARD_TERMS: dict[str, tuple[Callable[[StepValues, RewardParams], float], str | None]] = {
    "stage": (stage_term, None),
    "jerk": (jerk_term, "w_jerk"),
    "ik_failure": (ik_failure_term, "ik_cost"),
}


def weighted_terms(v: StepValues, p: RewardParams) -> list[tuple[str, float]]:
    """(name, weighted value) of every term, in `REWARD_TERMS` order."""
    out = []
    for name, (term, weight) in REWARD_TERMS.items():
        value = term(v, p)
        out.append((name, value if weight is None else getattr(p, weight) * value))
    return out
