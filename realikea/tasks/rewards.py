"""The paper's four gated reward stages with monotone baselines, plus jerk and IK costs.

Stage 1 approaches a pre-grasp target t1 with the jaws open, stage 2 refines towards t2,
stage 3 closes the jaws, stage 4 rewards opening. Each stage adds the maximum of the ones
before it (M1, M2, beta), so the reward never drops when a stage is reached.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RewardParams:
    """Constants of the appendix (DESIGN.md) plus the auxiliary cost weights."""

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

    @property
    def m1(self) -> float:
        """Saturation of stage 1: open bonus plus the approach term at d1 = 0."""
        return self.w_open1 + self.w_app1 * np.log(1.0 / self.eps)

    @property
    def m2(self) -> float:
        """Saturation of stage 2: approach term at d2 = 0 (no open bonus)."""
        return self.w_open2 + self.w_app2 * np.log(1.0 / self.eps)


def approach(d, weight: float, eps: float):
    """The logarithmic approach shaping w * (-log(d + eps))."""
    return weight * -np.log(np.asarray(d) + eps)


def open_reward(q, kappa: float):
    """kappa * log(100 q + 1): steep at q = 0 to reward breaking static friction."""
    return kappa * np.log(100.0 * np.maximum(np.asarray(q), 0.0) + 1.0)


def staged_reward(stage, d1, d2, aperture, q, p: RewardParams):
    """The reward of the active stage (1-4); all arguments broadcast over environments."""
    stage = np.asarray(stage)
    s_open = (np.asarray(aperture) > p.open_above).astype(float)
    s_close = (np.asarray(aperture) < p.close_below).astype(float)
    r1 = p.w_open1 * s_open + approach(d1, p.w_app1, p.eps)
    r2 = p.m1 + p.w_open2 * s_open + approach(d2, p.w_app2, p.eps)
    r3 = p.m1 + p.m2 + p.beta * s_close
    r4 = open_reward(q, p.kappa) + p.m1 + p.m2 + p.beta
    return np.select([stage == 1, stage == 2, stage == 3], [r1, r2, r3], r4)


def next_stage(stage, d1, d2, aperture, p: RewardParams):
    """Latched stage progress: 1 -> 2 within tau1 of t1, 2 -> 3 within tau2 of t2,
    3 -> 4 once the jaws are closed there (grasp readiness); a stage is never left."""
    stage = np.asarray(stage)
    closed = np.asarray(aperture) < p.close_below
    stage = np.where((stage == 1) & (np.asarray(d1) < p.tau1), 2, stage)
    stage = np.where((stage == 2) & (np.asarray(d2) < p.tau2), 3, stage)
    return np.where((stage == 3) & closed & (np.asarray(d2) < p.tau2), 4, stage)


def jerk_penalty(action, previous, before_previous, weight: float):
    """-w * ||a_t - 2 a_{t-1} + a_{t-2}||^2: discourages jerky commands."""
    second_difference = np.asarray(action) - 2 * np.asarray(previous) + np.asarray(before_previous)
    return -weight * np.sum(second_difference**2, axis=-1)
