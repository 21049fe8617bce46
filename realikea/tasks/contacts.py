"""Which force opens the front: the gripper's contact forces on the part, logged per control step.

During the pulling phase (the front moving open while the gripper pushes the part along the
opening direction u), each gripper-part contact's force on the part splits into its normal part
(n f_n) and its friction part (the tangential components). Their projections on u say what
carries the pull: normal forces (form closure: a finger behind a bar or under a lip, a wedge
behind a knob) or friction (a pinch, force closure). `strategy` names the episode from them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

STRATEGIES = ("hook", "lever", "pinch", "none")
# what `ContactLog.summary` reports per episode
SUMMARY_KEYS = (
    "strategy", "pull_seconds", "pull_normal", "pull_friction", "friction_share", "grip_force",
    "normal_angle_deg", "peak_pull", "peak_slip_ratio",
)  # fmt: skip


@dataclass(frozen=True)
class ClassifierParams:
    """Thresholds of the pulling phase and of the labels (conf/task/open.yaml: contacts)."""

    min_opening_rate: float  # m/s or rad/s: the front counts as opening above this
    min_pull: float  # N along u the gripper must put on the part for a pulling step
    min_samples: int  # pulling samples an episode needs before it gets a label other than none
    sample_substeps: int  # physics steps between two samples of the contact forces
    friction_share: float  # above this share of the pull carried by friction: pinch


@dataclass
class ContactLog:
    """Per-episode sums over the pulling samples of the gripper's forces on the part."""

    samples: int = 0
    normal: float = 0.0  # N along u carried by contact normal forces, summed over samples
    friction: float = 0.0  # N along u carried by friction forces
    grip: float = 0.0  # N of squeeze: half the sum of normal force magnitudes
    angle: float = 0.0  # rad*N: force-weighted angle between contact normal and u
    weight: float = 0.0  # N: total force weight of `angle`
    peak_pull: float = 0.0  # N: the largest pulling force of a sample
    peak_slip_ratio: float = 0.0  # that sample's friction pull / (mu * sum of normal forces)

    def summary(self, category: str, params: ClassifierParams, period: float) -> dict:
        """The episode's contact statistics (means over pulling samples `period` s apart) and
        its strategy label."""
        n = max(self.samples, 1)
        carried = max(self.normal, 0.0) + max(self.friction, 0.0)
        share = max(self.friction, 0.0) / carried if carried > 0 else 0.0
        return {
            "strategy": strategy(self.samples, share, category, params),
            "pull_seconds": self.samples * period,
            "pull_normal": self.normal / n,
            "pull_friction": self.friction / n,
            "friction_share": share,
            "grip_force": self.grip / n,
            "normal_angle_deg": math.degrees(self.angle / self.weight) if self.weight else 0.0,
            "peak_pull": self.peak_pull,
            "peak_slip_ratio": self.peak_slip_ratio,
        }


def strategy(samples: int, friction_share: float, category: str, params: ClassifierParams) -> str:
    """hook / lever (form closure on a bar or lip / on a knob), pinch (friction), or none."""
    if samples < params.min_samples:
        return "none"
    if friction_share > params.friction_share:
        return "pinch"
    return "lever" if category == "knob" else "hook"


class ContactMonitor:
    """Reads the gripper-part contact forces of one scene after each control step."""

    def __init__(self, model: mujoco.MjModel, gripper_bodies: list[int], part_geoms: list[int]):
        self.model = model
        self.gripper_bodies = np.asarray(gripper_bodies)
        self.part = np.zeros(model.ngeom, bool)
        self.part[part_geoms] = True
        self._force = np.zeros(6)

    def forces(self, data: mujoco.MjData) -> list[tuple[np.ndarray, np.ndarray, float]]:
        """(normal force, friction force, mu) on the part of every gripper-part contact."""
        out = []
        ncon = data.ncon
        if ncon == 0:
            return out
        geoms = data.contact.geom[:ncon]
        bodies = self.model.geom_bodyid[geoms]
        grip = np.isin(bodies, self.gripper_bodies)
        part = self.part[geoms]
        for k in np.flatnonzero((grip[:, 0] & part[:, 1]) | (grip[:, 1] & part[:, 0])):
            con = data.contact[k]
            if con.efc_address < 0:  # excluded or inactive
                continue
            mujoco.mj_contactForce(self.model, data, int(k), self._force)
            frame = con.frame.reshape(3, 3)
            sign = 1.0 if part[k, 1] else -1.0  # the force acts on geom2 along +normal
            normal = sign * self._force[0] * frame[0]
            friction = sign * (self._force[1] * frame[1] + self._force[2] * frame[2])
            out.append((normal, friction, float(con.friction[0])))
        return out

    def record(self, log: ContactLog, data, direction, rate: float, p: ClassifierParams):
        """Add the current state to the episode's log if the gripper is pulling the front open;
        `direction()` gives the opening direction u, computed only when it is needed."""
        if rate < p.min_opening_rate:
            return
        contacts = self.forces(data)
        if not contacts:
            return
        u = direction()
        normal = sum(float(n @ u) for n, _, _ in contacts)
        friction = sum(float(f @ u) for _, f, _ in contacts)
        pull = normal + friction
        if pull < p.min_pull:
            return
        magnitudes = [float(np.linalg.norm(n)) for n, _, _ in contacts]
        log.samples += 1
        log.normal += normal
        log.friction += friction
        log.grip += 0.5 * sum(magnitudes)
        for (n, _, _), m in zip(contacts, magnitudes, strict=True):
            if m > 0:
                cos = abs(float(n @ u)) / m
                log.angle += m * math.acos(min(cos, 1.0))
                log.weight += m
        if pull > log.peak_pull:
            capacity = sum(mu * m for (_, _, mu), m in zip(contacts, magnitudes, strict=True))
            log.peak_pull = pull
            log.peak_slip_ratio = max(friction, 0.0) / capacity if capacity > 0 else 0.0
