"""The `potential` reward variant: the gated variant's stages and shaping paid as a potential
(Ng, Harada and Russell 1999), so the only reward a policy can keep earning is the opening;
constants in `realikea/conf/task/reward/potential.yaml`.

Under `gated`, what a step pays for where the scene is (the stage's baseline, the approach, the
closing jaws, the hand at the handle) is paid again every step the scene stays there. That makes
every stage a place to rest, and losing a grasp costs the stage-4 premium (beta + hold, about 17
of 40 a step) for the rest of the episode. The reward screen's runs that did not learn settled on
exactly such places: holding a grasp without pulling (stage 4 in 0.91-0.98 of the episodes,
0.004-0.020 m opened, `experiments/reward_screen/README.md`), since a pull that slips loses the
premium for every remaining step while a centimetre opened earns 2 a step.

Here the same sum is a potential Phi(s), and a step pays its change, gamma Phi(s') - Phi(s):
reaching a stage pays its premium once, holding it pays slightly less than nothing
((gamma - 1) Phi), and a grasp that slips costs the premium once and earns it back when
regrasped. The opening (linear, plus the bonus at success) is the one reward paid every step,
and, as with `gated`'s `keep_opening`, from the episode's first grasp on, held or not: the
paper's "only after grasp readiness is achieved". Potential-based shaping leaves the optimal
policies of that opening reward unchanged (with gamma the learner's discount and Phi = 0 after
an early termination, `terminal`); the time-out at the horizon is bootstrapped by the learner,
so Phi is kept there.
"""

from __future__ import annotations

from dataclasses import dataclass

from realikea.errors import RealIkeaError
from realikea.tasks.rewards import gated
from realikea.tasks.rewards.terms import StepValues, bound_term, ik_failure_term, jerk_term

# the gated terms that depend only on where the scene is, and so make up the potential
POTENTIAL_TERMS = ("stage", "approach", "close", "center", "hold")


@dataclass(frozen=True)
class PotentialParams(gated.GatedParams):
    """The gated constants plus the discount the potential's change is taken with; the opening
    is kept once the episode has grasped."""

    gamma: float = 0.99
    keep_opening: bool = True

    def __post_init__(self):
        super().__post_init__()
        if not 0.0 < self.gamma <= 1.0:
            raise RealIkeaError(f"task.reward.gamma={self.gamma} must be in (0, 1]")


def potential(v: StepValues, p: PotentialParams) -> float:
    """Phi(s): the gated variant's stage baseline and shaping terms where the scene is, weighted,
    before `scale`; 0 after an early termination."""
    if v.terminal:
        return 0.0
    total = 0.0
    for name in POTENTIAL_TERMS:
        term, weight = gated.TERMS[name]
        value = term(v, p)
        total += value if weight is None else getattr(p, weight) * value
    return total


def shaping_term(v: StepValues, p: PotentialParams) -> float:
    """gamma Phi(s') - Phi(s): the potential's change over the step."""
    return p.gamma * potential(v, p) - v.prev_potential


# name -> (term, the params field that weighs it; None: the term carries its own weights)
TERMS = {
    "shaping": (shaping_term, None),
    "open": (gated.open_term, "w_progress"),
    "success": (gated.success_term, "success_bonus"),
    "push": (gated.push_term, "w_push"),
    "bound": (bound_term, "w_bound"),
    "jerk": (jerk_term, "w_jerk"),
    "ik_failure": (ik_failure_term, "ik_cost"),
}
