"""What every reward variant reads after a control step, and the formulas they share.

All functions take and return plain Python numbers for one environment: the task evaluates them
once per env and control step, where numpy's per-call overhead on scalars would cost more than
the arithmetic.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property


@dataclass(frozen=True)
class StageParams:
    """The constants both variants' stages share (the paper's appendix values but `w_open2`) and
    their saturations M1 and M2; each variant adds its own. A variant's params dataclass is its
    one schema: Hydra's `task/reward=<variant>` is built from its defaults."""

    eps: float = 0.01  # m: inside the approach terms' log
    w_open1: float = 2.0  # stage 1: open jaws (aperture > open_above) ...
    w_app1: float = 2.0  # ... and -log(d1 + eps) towards the pre-grasp target t1
    # stage 2: open jaws (the paper: 0, which lets the jaws close before they straddle the
    # handle, and `appendix` then reaches stage 4 with nothing in the grasp; why 2.0:
    # experiments/generalist/README.md, "The open-jaw bonus decides which source learns") ...
    w_open2: float = 2.0
    w_app2: float = 2.0  # ... and -log(d2 + eps) towards the grasp target t2
    beta: float = 10.0  # stage 4: its baseline above M1 + M2
    tau1: float = 0.05  # m: stage 2 within this of t1
    open_above: float = 0.6  # normalized aperture above this: open jaws
    close_below: float = 0.4  # below this: closed jaws (the observation's flag, appendix's gate)
    w_jerk: float = 0.05  # x -||a_t - 2 a_{t-1} + a_{t-2}||^2
    ik_cost: float = 1.0  # x -1 on a step whose IK target was infeasible

    @cached_property
    def m1(self) -> float:
        """Saturation of stage 1: open bonus plus the approach term at d1 = 0."""
        return self.w_open1 + self.w_app1 * math.log(1.0 / self.eps)

    @cached_property
    def m2(self) -> float:
        """Saturation of stage 2 above M1: its open bonus plus the approach term at d2 = 0."""
        return self.w_open2 + self.w_app2 * math.log(1.0 / self.eps)


@dataclass(frozen=True)
class StepValues:
    """What the reward terms read after one control step (plain Python numbers)."""

    stage: int
    d1: float  # TCP to the pre-grasp target t1 (m)
    d2: float  # TCP to the grasp target t2 (m)
    aperture: float  # normalized finger opening
    opening: float  # the front's displacement (m or rad)
    progress: float  # opening / the success threshold of the joint type
    straddle: bool  # the handle site lies between the two pads, near the line joining them
    engaged: bool  # grasp readiness: a pinch (straddling, both fingers on the part) or a hook
    action: list[float]
    prev_action: list[float]
    prev_prev_action: list[float]
    ik_ok: bool
    offset: float = math.inf  # m: the handle site from the line joining the pads, if between them
    push: float = 0.0  # N at the handle: the force pressing the front against its closed stop
    grasped: bool = False  # the stage has been 4 at some step of the episode, this one included
    excess: float = 0.0  # sum of (|a_i| - 1)^2 over the policy's action beyond the clip to [-1, 1]
    prev_progress: float = 0.0  # progress after the previous step (or the reset)


def approach(d: float, weight: float, eps: float) -> float:
    """The logarithmic approach shaping w * (-log(d + eps))."""
    return weight * -math.log(d + eps)


def jerk_penalty(action, previous, before_previous, weight: float) -> float:
    """-w * ||a_t - 2 a_{t-1} + a_{t-2}||^2 (sequences of floats): discourages jerky commands."""
    total = 0.0
    for a, b, c in zip(action, previous, before_previous, strict=True):
        second_difference = a - 2.0 * b + c
        total += second_difference * second_difference
    return -weight * total


def jerk_term(v: StepValues, p) -> float:
    """-||a_t - 2 a_{t-1} + a_{t-2}||^2, before its weight."""
    return jerk_penalty(v.action, v.prev_action, v.prev_prev_action, 1.0)


def bound_term(v: StepValues, p) -> float:
    """-sum (|a_i| - 1)^2 beyond the clip, before its weight: a policy whose mean has drifted
    past the clip explores nothing on that component (every sample clips to the same command)."""
    return -v.excess


def ik_failure_term(v: StepValues, p) -> float:
    """-1 on a step whose IK target was infeasible, before its weight."""
    return 0.0 if v.ik_ok else -1.0
