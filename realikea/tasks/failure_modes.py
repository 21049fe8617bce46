"""Why an episode failed: the paper's four failure modes (appendix, "The Four Characteristic
Failure Modes"), read from the gripper's contact forces, the robot's contacts with the scene and
the wrist over the whole episode, whether the front moved or not.

- slip: a grasp carried pull on the front (at least `carried_pull` N along the opening direction,
  the jaws having squeezed the front with at least `squeeze` N: a pinch, not a push) and lost
  it: no such pull for the last `lost_seconds` of the episode, or its last carrying sample had
  its friction at `saturated` of the contacts' capacity (sliding, not holding);
- mutual_interference: the robot pressed the scene off the moving front (a neighbouring front,
  the worktop, the carcass) with at least `blocked_force` N for `blocked_seconds`;
- narrow_clearance: the hand reached the part (touched it, or its TCP came within `reach` m of
  the handle) but no finger got behind or under it (normal force along the opening direction
  below `behind_pull` N);
- specialized_design: the same, on a part that needs a wrist turn to catch it (a knob's lever, a
  finger pull's lip: the hook oracle's wedge pitches) that the policy never made (pitch never
  `turn` rad from where the episode began);
- other: anything else (the part never reached; a grasp that held to the end but opened too
  little; a finger behind the part that lost it).

The modes are tested in that order, so a slipping grasp is a slip even next to the worktop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

FAILURE_MODES = (
    "slip", "mutual_interference", "narrow_clearance", "specialized_design", "other"
)  # fmt: skip
# categories caught only with the wrist turned (realikea/conf/policy/hook_oracle.yaml:
# wedge_pitch for a knob's head, lip_pitch for a finger pull's lip)
NEEDS_TURN = ("knob", "finger_pull")
# what an episode's record carries of its failure evidence (`FailureLog.summary`)
FAILURE_KEYS = (
    "failure_mode", "carried_pull", "behind_pull", "closest_reach", "blocked_seconds",
    "wrist_turn",
)  # fmt: skip


@dataclass(frozen=True)
class FailureParams:
    """Thresholds of the failure modes (realikea/conf/eval.yaml: contacts.failure)."""

    carried_pull: float  # N along u on the front: a grasp that carried at least this pulled
    lost_seconds: float  # s at the end without that pull, after carrying it: the grasp was lost
    saturated: float  # friction / capacity at the last carrying sample at or above: sliding
    squeeze: float  # N the jaws squeezed the front against each other: a grasp
    reach: float  # m, TCP to the handle: the hand reached the part
    behind_pull: float  # N of normal force along u on the front: a finger behind or under it
    blocked_force: float  # N of the robot's normal force on the scene off the moving front
    blocked_seconds: float  # s of it that count as interference
    turn: float  # rad of wrist pitch away from the episode's first: the wrist was turned


@dataclass
class FailureLog:
    """Per-episode evidence, one update per contact sample."""

    samples: int = 0
    carried: float = 0.0  # N: the largest pull of the gripper on the front along u
    last_carry: int = -1  # index of the last sample pulling at least carried_pull
    last_saturation: float = 0.0  # friction / capacity of that sample
    squeeze: float = 0.0  # N: the largest opposing normal force on the front
    behind: float = 0.0  # N: the largest normal pull along u on the front
    closest: float = math.inf  # m: the TCP's closest approach to the handle
    touched: int = 0  # samples with the gripper touching the part
    blocked: int = 0  # samples of the robot pressing the scene off the front
    start_pitch: float | None = None
    turned: float = 0.0  # rad: the largest |pitch - start_pitch|

    def summary(self, outcome: str, category: str, p: FailureParams, period: float) -> dict:
        """The episode's failure mode (None for a success) and its evidence."""
        failed = outcome != "success"
        return {
            "failure_mode": failure_mode(self, category, p, period) if failed else None,
            "carried_pull": self.carried,
            "behind_pull": self.behind,
            "closest_reach": self.closest if math.isfinite(self.closest) else None,
            "blocked_seconds": self.blocked * period,
            "wrist_turn": self.turned,
        }


def failure_mode(log: FailureLog, category: str, p: FailureParams, period: float) -> str:
    """The failure mode of a failed episode from its log (see the module docstring)."""
    pulled = log.carried >= p.carried_pull
    lost = pulled and (log.samples - 1 - log.last_carry) * period >= p.lost_seconds
    sliding = lost or log.last_saturation >= p.saturated
    if pulled and sliding and log.squeeze >= p.squeeze:
        return "slip"
    if log.blocked * period >= p.blocked_seconds:
        return "mutual_interference"
    if pulled and not lost:  # held to the end: too slow or too short, not one of the modes
        return "other"
    reached = log.touched > 0 or log.closest <= p.reach
    if reached and log.behind < p.behind_pull:
        if category in NEEDS_TURN and log.turned < p.turn:
            return "specialized_design"
        return "narrow_clearance"
    return "other"


class FailureMonitor:
    """Samples one scene's evidence: the gripper's pull on the front (from `ContactMonitor`'s
    forces), the robot's contacts with the rest of the scene, the TCP and the wrist."""

    def __init__(self, model: mujoco.MjModel, robot_geoms: list[int], moving_geoms: list[int]):
        self.model = model
        self.robot = np.zeros(model.ngeom, bool)
        self.robot[robot_geoms] = True
        self.scene = ~self.robot
        self.scene[moving_geoms] = False
        self._force = np.zeros(6)

    def pressing(self, data: mujoco.MjData) -> float:
        """N of normal force between the robot and the scene off the moving front."""
        ncon = data.ncon
        if ncon == 0:
            return 0.0
        geoms = data.contact.geom[:ncon]
        hits = (self.robot[geoms[:, 0]] & self.scene[geoms[:, 1]]) | (
            self.robot[geoms[:, 1]] & self.scene[geoms[:, 0]]
        )
        total = 0.0
        for k in np.flatnonzero(hits):
            if data.contact[k].efc_address >= 0:
                mujoco.mj_contactForce(self.model, data, int(k), self._force)
                total += abs(float(self._force[0]))
        return total

    def record(
        self, log: FailureLog, data, contacts, u, reach: float, pitch: float, p: FailureParams
    ) -> None:
        """Add one sample: `contacts` as `ContactMonitor.forces` gives them, `u` the opening
        direction (None without contacts), `reach` the TCP-handle distance, `pitch` the wrist's."""
        index = log.samples
        log.samples += 1
        log.closest = min(log.closest, reach)
        if log.start_pitch is None:
            log.start_pitch = pitch
        log.turned = max(log.turned, abs(pitch - log.start_pitch))
        if self.pressing(data) >= p.blocked_force:
            log.blocked += 1
        if not contacts:
            return
        log.touched += int(any(on_part for _, _, _, on_part in contacts))
        # normal forces that cancel: the jaws against each other, not the hand pushing
        magnitude = sum(float(np.linalg.norm(c[0])) for c in contacts)
        resultant = float(np.linalg.norm(sum(c[0] for c in contacts)))
        log.squeeze = max(log.squeeze, 0.5 * (magnitude - resultant))
        # on the part and on the rest of the front apart, each counting only when it pulls (a
        # finger pressing the panel closed while the other pulls the bar cancels nothing)
        pull = behind = friction = 0.0
        for on_part in (True, False):
            n = sum(float(c[0] @ u) for c in contacts if c[3] == on_part)
            f = sum(float(c[1] @ u) for c in contacts if c[3] == on_part)
            if n + f > 0:
                pull, friction = pull + n + f, friction + max(f, 0.0)
            behind = max(behind, n)
        log.behind = max(log.behind, behind)
        log.carried = max(log.carried, pull)
        if pull >= p.carried_pull:
            capacity = sum(mu * float(np.linalg.norm(n)) for n, _, mu, _ in contacts)
            log.last_carry = index
            log.last_saturation = friction / capacity if capacity > 0 else 0.0
