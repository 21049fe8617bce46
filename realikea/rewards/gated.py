"""The `gated` reward variant (the default): the paper's four stages, but each step's stage is
read from the scene as it is then, with grasp readiness from contact; constants in
`GatedParams`. What showed each choice:
`experiments/reward_screen/README.md` ("Why the gated reward is built this way").

The paper credits opening "only after grasp readiness is achieved", with "only one stage
contribution active under mutually exclusive gating". Here, every step:

- stage 4 (engaged, `realikea/tasks/grip.py`): a pinch, with the handle site between the pads
  and both fingers touching the part, or form closure, a finger touching the part where its
  surface faces the front panel (behind a bar, under a lip, behind a knob's head). Closed empty
  jaws at the handle are neither, while a pinch of a knob wider than the jaws can close to is
  one;
- stage 3 (straddling): the handle site between the pads, within `straddle_radius` of the line
  joining them, as Isaac Lab's cabinet task gates on the fingers being on either side of the
  handle, whatever the collision geometry makes of the handle's surface. `w_center` (0 by
  default) adds a term for the handle site's nearness to that line, meant to make the jaws close
  on the handle rather than beside it; `w_app3` (0 by default) pays stage 3 the approach to the
  grasp target t2, at most `w_hold` so a grasp at the same place still pays more;
- stage 2: within tau1 of the pre-grasp target t1, or within `refine_radius` of t2;
- stage 1 otherwise. A lost grasp returns the stage to the approach.

Every stage, `w_push` (0 by default) costs pressing the closed front shut, in proportion to the
force its closed stop holds at the handle (`OpenTask.pressing_force`), capped at `push_force`;
`w_bound` (0 by default) costs the policy's action beyond its clip to [-1, 1], where a mean far
past the clip explores nothing on that component.

The opening:

- `keep_opening`: the opening, its increase and its bonus are paid in every stage once the
  episode has been in stage 4, so a pinch that slips on the way out keeps the opening it made;
- `w_progress` and `success_bonus` are large enough that a pull that opens 5 cm and slips pays
  more a step than holding the grasp still;
- `w_rate` (10 x `w_progress`) pays the capped opening's increase over the step, so over an
  episode it sums to the opening made, and closing the front again costs what it paid (the level
  alone pays a pull only through the steps after it).

Each stage's baseline is the maximum of the ones before it (M1, M2, beta), so reaching a stage
never lowers the reward. Stage 4 keeps the hand at the handle (`hold`, the approach shaping of
t2) and pays the opening linearly in opening / success threshold plus a bonus from the
threshold on (20 cm or 45 deg): no resting place short of success. `open_target` (1 by default)
caps that level: above 1 it also pays opening past the threshold, so a front opened just past it,
then nudged back as the hand lets go, is no longer where the reward stops. `reopen_bonus`
(true by default) pays stages 1 and 2 their open jaws after the episode's first grasp too; off,
a hand whose hook came off the handle is not paid to open its jaws, which let a door fall back
(`experiments/generalist/README.md`, "A partial is a grasp let go"). Every term is
multiplied by `scale` so a step held at success pays about 2 and value targets stay O(1-200) at
gamma = 0.99, within reach of rsl-rl's clipping of value updates to +-0.2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

from realikea.errors import RealIkeaError
from realikea.rewards.terms import (
    StageParams,
    StepValues,
    approach,
    bound_term,
    ik_failure_term,
    jerk_term,
)


@dataclass(frozen=True)
class GatedParams(StageParams):
    """The gated variant's constants: `task/reward=gated` (the default) is built from these."""

    scale: float = 0.01  # every term: a step held at success pays about 2, value targets O(1-200)
    w_close: float = 5.0  # stage 3 (straddling): x (1 - aperture)
    # stage 3: x (1 - the handle site's distance from the pads' line / straddle_radius)
    w_center: float = 0.0
    w_app3: float = 0.0  # stage 3: x -log(d2 + eps) towards t2 (at most w_hold)
    w_hold: float = 2.0  # stage 4: x -log(d2 + eps), the hand stays at the handle
    w_progress: float = 120.0  # stage 4: x min(opening / success threshold, 1)
    w_rate: float = 1200.0  # stage 4: x that level's increase over the step
    success_bonus: float = 60.0  # stage 4: from the success threshold on (20 cm, 45 deg)
    refine_radius: float = 0.11  # m: stage 2 within this of t2 (|o1 - o2| = 6 cm plus tau1)
    straddle_radius: float = 0.025  # m: stage 3 with the handle site this near the pads' line
    # deg: stage 4 when a finger touches the part where its surface faces the front panel within
    # this of the pull direction, reversed
    hook_angle: float = 70.0
    w_push: float = 0.0  # every stage: x -min(force pressing the closed front shut / push_force, 1)
    w_bound: float = 0.0  # every step: x -sum (|a_i| - 1)^2 of the action beyond its clip
    keep_opening: bool = True  # w_progress, w_rate, success_bonus paid in any stage once in stage 4
    # stage 4: the opening level (opening / success threshold) is paid up to this, at least 1
    open_target: float = 1.0
    # stages 1 and 2 pay open jaws after the episode's first grasp too (false: only before it)
    reopen_bonus: bool = True
    push_force: float = 400.0  # N at the handle

    def __post_init__(self):
        if self.open_target < 1.0:
            raise RealIkeaError(
                f"task.reward: open_target={self.open_target} must be >= 1 (a cap below the "
                "success threshold is a resting place short of success)"
            )
        if self.beta < self.w_close + self.w_center:
            raise RealIkeaError(
                f"task.reward: beta={self.beta} must be >= w_close + w_center = "
                f"{self.w_close + self.w_center} (a grasp must pay at least what straddling the "
                "handle with closed jaws does)"
            )
        if self.w_app3 > self.w_hold:
            raise RealIkeaError(
                f"task.reward: w_app3={self.w_app3} must be <= w_hold={self.w_hold} (at the same "
                "place, a grasp must pay more than straddling the handle does)"
            )

    @cached_property
    def hook_cos(self) -> float:
        """cos(hook_angle): a contact hooks when the part's normal there is this close to -u."""
        return math.cos(math.radians(self.hook_angle))


def next_stage(stage: int, v: StepValues, p: GatedParams) -> int:
    """The stage of the scene as it is after the step (the previous stage plays no part)."""
    if v.engaged:
        return 4
    if v.straddle:
        return 3
    if v.d1 < p.tau1 or v.d2 < p.refine_radius:
        return 2
    return 1


def stage_term(v: StepValues, p: GatedParams) -> float:
    """The active stage's baseline: 0, M1, M1 + M2, M1 + M2 + beta."""
    return (0.0, p.m1, p.m1 + p.m2, p.m1 + p.m2 + p.beta)[v.stage - 1]


def approach_term(v: StepValues, p: GatedParams) -> float:
    """Stages 1 and 2: open jaws (unless `reopen_bonus` is off and the episode has grasped) and
    the log approach to t1, then to t2 (the appendix's)."""
    if v.stage > 2:
        return 0.0
    paid = p.reopen_bonus or not v.grasped
    s_open = 1.0 if paid and v.aperture > p.open_above else 0.0
    if v.stage == 1:
        return p.w_open1 * s_open + approach(v.d1, p.w_app1, p.eps)
    return p.w_open2 * s_open + approach(v.d2, p.w_app2, p.eps)


def close_term(v: StepValues, p: GatedParams) -> float:
    """Stage 3: how far the jaws have closed around the handle (0 open .. 1 closed)."""
    return min(max(1.0 - v.aperture, 0.0), 1.0) if v.stage == 3 else 0.0


def center_term(v: StepValues, p: GatedParams) -> float:
    """Stage 3: how near the handle site is to the line joining the pads (1 on it, 0 at the
    straddle's radius), so the jaws close on the handle rather than beside it."""
    return max(1.0 - v.offset / p.straddle_radius, 0.0) if v.stage == 3 else 0.0


def approach3_term(v: StepValues, p: GatedParams) -> float:
    """Stage 3: the log approach to t2, so straddling jaws advance onto the grasp target."""
    return approach(v.d2, 1.0, p.eps) if v.stage == 3 else 0.0


def hold_term(v: StepValues, p: GatedParams) -> float:
    """Stage 4: the log approach to t2, so the hand stays at the handle while it pulls."""
    return approach(v.d2, 1.0, p.eps) if v.stage == 4 else 0.0


def credits_opening(v: StepValues, p: GatedParams) -> bool:
    """Whether the opening is paid this step: in stage 4, or with `keep_opening` in any stage
    once the episode has been in stage 4 (the paper credits opening "only after grasp readiness
    is achieved")."""
    return v.stage == 4 or (p.keep_opening and v.grasped)


def capped(progress: float, target: float) -> float:
    """Opening / success threshold, clipped to [0, target]."""
    return min(max(progress, 0.0), target)


def open_term(v: StepValues, p: GatedParams) -> float:
    """Opening / success threshold, capped at `open_target`: linear, no resting place short of
    success."""
    return capped(v.progress, p.open_target) if credits_opening(v, p) else 0.0


def rate_term(v: StepValues, p: GatedParams) -> float:
    """The capped opening's increase over the step, where the opening is paid."""
    if not credits_opening(v, p):
        return 0.0
    return capped(v.progress, p.open_target) - capped(v.prev_progress, p.open_target)


def success_term(v: StepValues, p: GatedParams) -> float:
    """1 once the opening reaches the success threshold."""
    return 1.0 if credits_opening(v, p) and v.progress >= 1.0 else 0.0


def push_term(v: StepValues, p: GatedParams) -> float:
    """Every stage: -(the force pressing the closed front shut / push_force), capped at -1."""
    return -min(v.push / p.push_force, 1.0)


# name -> (term, the params field that weighs it; None: the term carries its own weights)
TERMS = {
    "stage": (stage_term, None),
    "approach": (approach_term, None),
    "close": (close_term, "w_close"),
    "center": (center_term, "w_center"),
    "approach3": (approach3_term, "w_app3"),
    "hold": (hold_term, "w_hold"),
    "open": (open_term, "w_progress"),
    "rate": (rate_term, "w_rate"),
    "success": (success_term, "success_bonus"),
    "push": (push_term, "w_push"),
    "bound": (bound_term, "w_bound"),
    "jerk": (jerk_term, "w_jerk"),
    "ik_failure": (ik_failure_term, "ik_cost"),
}
