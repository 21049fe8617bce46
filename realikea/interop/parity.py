"""Whether PyBullet agrees with MuJoCo: verdicts and differences of the pull and probe checks."""

from __future__ import annotations

from dataclasses import dataclass

from omegaconf import OmegaConf

from realikea.files import CONF_DIR
from realikea.interop.probe import BLOCKED
from realikea.interop.pull import Trajectory

TOLERANCE = 0.10  # largest relative difference of the openings that counts as agreement
SECONDS = 1.0  # how long the pull lasts
# a front that moved less than this in the pull stayed still (tests/test_physics.py's bounds)
STILL = {"slide": 1e-3, "hinge": 2e-3}  # m, rad
# a front that moved at least this opened: the task's partial opening (2 cm or 5 degrees)
OPENS = dict(OmegaConf.load(CONF_DIR / "task" / "open.yaml").outcome.partial)


def relative_difference(reference: float, other: float) -> float:
    """|other - reference| / |reference| (inf where the reference is 0 and the other is not)."""
    if reference == 0:
        return 0.0 if other == 0 else float("inf")
    return abs(other - reference) / abs(reference)


def moved(trajectory: Trajectory, joint_type: str) -> str:
    """still, opens, or between: what the front did in the pull's `SECONDS`."""
    opening = trajectory.at(SECONDS)
    if abs(opening) < STILL[joint_type]:
        return "still"
    return "opens" if opening >= OPENS[joint_type] else "between"


def comparison_time(reference: Trajectory, upper: float) -> float:
    """When the openings are compared clear of the joint's stop: the time MuJoCo's front
    reaches half its range, or `SECONDS` if it never does."""
    reached = reference.time_to(upper / 2)
    return SECONDS if reached is None else min(reached, SECONDS)


@dataclass(frozen=True)
class PullParity:
    """One pull in both simulators: openings, their differences and the verdict."""

    expected: str  # still | opens
    mujoco: float  # opening after SECONDS
    pybullet: float
    difference: float | None  # relative, after SECONDS (None where both stayed still)
    compare_time: float  # s: the second comparison, clear of the stop
    mujoco_then: float
    pybullet_then: float
    difference_then: float | None
    mujoco_moved: str
    pybullet_moved: str

    @property
    def passed(self) -> bool:
        """Both did what the pull should do and, where they moved, agree within TOLERANCE."""
        if self.mujoco_moved != self.expected or self.pybullet_moved != self.expected:
            return False
        if self.expected == "still":
            return True
        return self.difference <= TOLERANCE and self.difference_then <= TOLERANCE


def compare_pull(
    mujoco: Trajectory, pybullet: Trajectory, joint_type: str, upper: float, expected: str
) -> PullParity:
    """Compare one pull's trajectories (`expected`: still below breakaway, opens above it)."""
    t = comparison_time(mujoco, upper)
    both_still = expected == "still"
    return PullParity(
        expected=expected,
        mujoco=mujoco.at(SECONDS),
        pybullet=pybullet.at(SECONDS),
        difference=None
        if both_still
        else relative_difference(mujoco.at(SECONDS), pybullet.at(SECONDS)),
        compare_time=t,
        mujoco_then=mujoco.at(t),
        pybullet_then=pybullet.at(t),
        difference_then=None if both_still else relative_difference(mujoco.at(t), pybullet.at(t)),
        mujoco_moved=moved(mujoco, joint_type),
        pybullet_moved=moved(pybullet, joint_type),
    )


@dataclass(frozen=True)
class ProbeParity:
    """One probe run in both simulators: how far the fingertip went and whether it should pass."""

    expected: str  # passes (CoACD keeps the gap open) | blocked (the hull seals it)
    through: float  # m of travel that clear the part
    mujoco: float  # m travelled
    pybullet: float

    def outcome(self, travel: float) -> str:
        """passes, blocked or stuck (stopped inside the part) for a travel."""
        if travel > self.through:
            return "passes"
        return "blocked" if travel < BLOCKED else "stuck"

    @property
    def passed(self) -> bool:
        """Both simulators give the expected outcome."""
        return self.outcome(self.mujoco) == self.expected == self.outcome(self.pybullet)
