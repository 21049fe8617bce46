"""Which force opens the front: the gripper's contact forces on the moving front, logged per
control step.

During the pulling phase (the front moving open while the gripper pushes it along the opening
direction u), each gripper contact's force on the moving front splits into its normal part
(n f_n) and its friction part (the tangential components). Their projections on u say what
carries the pull: normal forces (form closure: a finger behind a bar or under a lip, a wedge
behind a knob) or friction (a pinch, force closure). Contacts on the part and on the rest of
the front (the panel, its edges) are summed apart, so an opening through the panel's edge is
named as such (`front_hook`, `front_pinch`) rather than credited to the part, and a finger
pressing the panel closed (wedged between a bar and the panel) does not cancel the pull the
part carries: each place counts only when it pulls.
`strategy` names the episode from these sums.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

STRATEGIES = ("hook", "lever", "pinch", "front_hook", "front_pinch", "none")
# what `ContactLog.summary` reports per episode
SUMMARY_KEYS = (
    "strategy", "pull_seconds", "pull_normal", "pull_friction", "friction_share", "front_share",
    "grip_force", "normal_angle_deg", "peak_pull", "peak_slip_ratio",
)  # fmt: skip
# what `sample_forces` gives for one sample of the contacts (N)
SAMPLE_FORCES = ("part_normal", "part_friction", "front_normal", "front_friction", "grip")


@dataclass(frozen=True)
class ClassifierParams:
    """Thresholds of the pulling phase and of the labels (realikea/conf/task/open.yaml:
    contacts)."""

    min_opening_rate: float  # m/s or rad/s: the front counts as opening above this
    min_pull: float  # N along u the gripper must put on the part for a pulling step
    min_samples: int  # pulling samples an episode needs before it gets a label other than none
    sample_substeps: int  # physics steps between two samples of the contact forces
    friction_share: float  # above this share of the pull carried by friction: pinch
    front_share: float  # above this share of the pull carried off the part: front_hook/pinch


@dataclass
class ContactLog:
    """Per-episode sums over the pulling samples of the gripper's forces on the part and, apart,
    on the rest of the moving front."""

    samples: int = 0
    normal: float = 0.0  # N along u of the normal forces on the part, summed over samples
    friction: float = 0.0  # N along u of the friction forces on the part
    front_normal: float = 0.0  # N along u of the normal forces on the front, off the part
    front_friction: float = 0.0  # N along u of the friction forces on the front, off the part
    grip: float = 0.0  # N of squeeze: half the sum of normal force magnitudes
    angle: float = 0.0  # rad*N: force-weighted angle between contact normal and u
    weight: float = 0.0  # N: total force weight of `angle`
    peak_pull: float = 0.0  # N: the largest pulling force of a sample
    peak_slip_ratio: float = 0.0  # that sample's friction pull / (mu * sum of normal forces)

    def summary(self, category: str, params: ClassifierParams, period: float) -> dict:
        """The episode's contact statistics (means over pulling samples `period` s apart) and
        its strategy label."""
        n = max(self.samples, 1)
        # what pulls: forces along -u (pressing the front closed) carry nothing
        on_part = max(self.normal, 0.0) + max(self.friction, 0.0)
        off_part = max(self.front_normal, 0.0) + max(self.front_friction, 0.0)
        carried = on_part + off_part
        by_friction = max(self.friction, 0.0) + max(self.front_friction, 0.0)
        share = by_friction / carried if carried > 0 else 0.0
        front = off_part / carried if carried > 0 else 0.0
        return {
            "strategy": strategy(self.samples, share, front, category, params),
            "pull_seconds": self.samples * period,
            "pull_normal": self.normal / n,
            "pull_friction": self.friction / n,
            "friction_share": share,
            "front_share": front,
            "grip_force": self.grip / n,
            "normal_angle_deg": math.degrees(self.angle / self.weight) if self.weight else 0.0,
            "peak_pull": self.peak_pull,
            "peak_slip_ratio": self.peak_slip_ratio,
        }


def strategy(
    samples: int, friction_share: float, front_share: float, category: str, params: ClassifierParams
) -> str:
    """hook / lever (form closure on a bar or lip / on a knob), pinch (friction), front_hook /
    front_pinch (the same through the front off the part: over its edge, squeezing it), or none."""
    if samples < params.min_samples:
        return "none"
    pinch = friction_share > params.friction_share
    if front_share > params.front_share:
        return "front_pinch" if pinch else "front_hook"
    if pinch:
        return "pinch"
    return "lever" if category == "knob" else "hook"


class ContactMonitor:
    """Reads the gripper's contact forces on the moving front of one scene between substeps."""

    def __init__(
        self,
        model: mujoco.MjModel,
        gripper_bodies: list[int],
        part_geoms: list[int],
        front_geoms: list[int],
    ):
        self.model = model
        self.gripper_bodies = np.asarray(gripper_bodies)
        self.part = np.zeros(model.ngeom, bool)
        self.part[part_geoms] = True
        self.moving = self.part.copy()
        self.moving[front_geoms] = True
        self._force = np.zeros(6)

    def forces(self, data: mujoco.MjData) -> list[tuple[np.ndarray, np.ndarray, float, bool]]:
        """(normal force, friction force, mu, on the part) on the front of every gripper contact
        with the moving front."""
        out = []
        ncon = data.ncon
        if ncon == 0:
            return out
        geoms = data.contact.geom[:ncon]
        bodies = self.model.geom_bodyid[geoms]
        grip = np.isin(bodies, self.gripper_bodies)
        moving = self.moving[geoms]
        for k in np.flatnonzero((grip[:, 0] & moving[:, 1]) | (grip[:, 1] & moving[:, 0])):
            con = data.contact[k]
            if con.efc_address < 0:  # excluded or inactive
                continue
            mujoco.mj_contactForce(self.model, data, int(k), self._force)
            frame = con.frame.reshape(3, 3)
            second = bool(moving[k, 1])
            sign = 1.0 if second else -1.0  # the force acts on geom2 along +normal
            normal = sign * self._force[0] * frame[0]
            friction = sign * (self._force[1] * frame[1] + self._force[2] * frame[2])
            on_part = bool(self.part[geoms[k, 1 if second else 0]])
            out.append((normal, friction, float(con.friction[0]), on_part))
        return out

    def record(self, log: ContactLog, contacts, u, rate: float, p: ClassifierParams):
        """Add one sample to the episode's log if the gripper is pulling the front open:
        `contacts` as `forces` gives them, `u` the opening direction, `rate` the front's."""
        if rate < p.min_opening_rate or not contacts:
            return
        along = _along(contacts, u)
        normal, friction, front_normal, front_friction = _pull_sums(along)
        # each place counts only when it pulls (a finger pressing the panel closed is no pull)
        pulls = [max(normal + friction, 0.0), max(front_normal + front_friction, 0.0)]
        pull = sum(pulls)
        if pull < p.min_pull:
            return
        magnitudes = [float(np.linalg.norm(n)) for n, _, _, _ in contacts]
        log.samples += 1
        log.normal += normal
        log.friction += friction
        log.front_normal += front_normal
        log.front_friction += front_friction
        log.grip += 0.5 * sum(magnitudes)
        for (n_along, _, _), m in zip(along, magnitudes, strict=True):
            if m > 0:
                log.angle += m * math.acos(min(abs(n_along) / m, 1.0))
                log.weight += m
        if pull > log.peak_pull:
            capacity = sum(mu * m for (_, _, mu, _), m in zip(contacts, magnitudes, strict=True))
            by_friction = (friction if pulls[0] else 0.0) + (front_friction if pulls[1] else 0.0)
            log.peak_pull = pull
            log.peak_slip_ratio = max(by_friction, 0.0) / capacity if capacity > 0 else 0.0


def _along(contacts, u) -> list[tuple[float, float, bool]]:
    """(normal, friction, on the part) of every contact, projected on the opening direction u."""
    return [(float(n @ u), float(f @ u), part) for n, f, _, part in contacts]


def _pull_sums(along) -> tuple[float, float, float, float]:
    """Normal and friction force along u on the part, then on the front off the part."""
    normal = sum(n for n, _, part in along if part)
    friction = sum(f for _, f, part in along if part)
    front_normal = sum(n for n, _, part in along if not part)
    front_friction = sum(f for _, f, part in along if not part)
    return normal, friction, front_normal, front_friction


def sample_forces(contacts, u) -> tuple[float, ...]:
    """One sample's `SAMPLE_FORCES`: the gripper's normal and friction force along the opening
    direction u on the part and on the front off it (positive pulls the front open), and its
    grip (half the sum of the normal force magnitudes); all zero without contacts."""
    if not contacts:
        return (0.0,) * len(SAMPLE_FORCES)
    grip = 0.5 * sum(float(np.linalg.norm(n)) for n, _, _, _ in contacts)
    return (*_pull_sums(_along(contacts, u)), grip)
