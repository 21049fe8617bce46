"""Scripted policies as waypoint plans: servo the TCP through poses, then pull along the front.

A plan is made per episode from the scene's `SceneFacts`; `act` turns the current waypoint into
the task's 5-D action (the same action a learned policy emits, saturated at the task's scales).
A plan that finds nothing to do on a part (`NoPlan`) holds still with the gripper open for that
episode, its reason kept as the episode's note (`WaypointPolicy.note`).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass

import numpy as np

from realikea.policies.per_env import PerEnvPolicy
from realikea.sim.ik import tcp_pitch
from realikea.tasks import observations
from realikea.tasks.facts import SceneFacts
from realikea.tasks.open_task import ACTION_SIZE

OPEN, CLOSE = 1.0, -1.0  # gripper commands (a4)
_SLICES = observations.slices()
_HOLD = np.array([0.0, 0.0, 0.0, 0.0, OPEN])  # no motion, gripper open


class NoPlan(Exception):
    """Raised by `plan` when the episode's part offers nothing to do; the message says why."""


@dataclass(frozen=True)
class Waypoint:
    """Hold the TCP at `pos` (world) with `pitch` and gripper command `grip`.

    The waypoint is done once the TCP is within `tolerance` (m) and `hold` more steps have
    passed, or after `timeout` steps whatever happens. `name` says what it is for (e.g.
    "catch", "pull"), for measurements that read where an episode is in its plan.
    """

    pos: np.ndarray
    pitch: float
    grip: float
    tolerance: float = 0.005
    hold: int = 0
    timeout: int = 40
    name: str = ""


@dataclass(frozen=True)
class ActionScales:
    """The task's action scales (realikea/conf/task/open.yaml: action)."""

    translation: float = 0.01  # m per unit command
    pitch: float = 0.04  # rad per unit command


def tcp_state(obs: np.ndarray, facts: SceneFacts) -> tuple[np.ndarray, float]:
    """World TCP position and pitch from one observation row."""
    pos = obs[_SLICES["tcp_pos"]] + facts.robot_base
    two = obs[_SLICES["tcp_rot6d"]].reshape(2, 3).T
    rotation = np.column_stack([two, np.cross(two[:, 0], two[:, 1])])
    return pos, tcp_pitch(rotation, facts.tcp_nominal)


def servo(obs: np.ndarray, facts: SceneFacts, wp: Waypoint, scales: ActionScales) -> np.ndarray:
    """The action that moves the TCP towards a waypoint as fast as the action scales allow."""
    pos, pitch = tcp_state(obs, facts)
    action = np.empty(ACTION_SIZE)
    action[0] = (wp.pitch - pitch) / scales.pitch
    action[1:4] = (wp.pos - pos) / scales.translation
    longest = np.max(np.abs(action[1:4]))
    if longest > 1.0:  # keep the direction of motion when the step saturates
        action[1:4] /= longest
    action[4] = wp.grip
    return np.clip(action, -1.0, 1.0)


class WaypointPolicy(PerEnvPolicy):
    """Base of the scripted policies: `plan(facts)` gives each episode's waypoints."""

    name = "scripted"

    def __init__(self, scales: ActionScales = ActionScales()):
        self.scales = scales
        self.plans: dict[int, list[Waypoint]] = {}
        self.facts: dict[int, SceneFacts] = {}
        self.phase: dict[int, int] = {}
        self.count: dict[int, int] = {}
        self.reached: dict[int, int] = {}
        self.note: dict[int, str] = {}  # why an env's current episode has no plan (if it has none)
        self._warned: set[str] = set()

    @classmethod
    def from_config(cls, cfg):
        """The task's action scales; subclasses read their own `cfg.policy` settings."""
        action = cfg.task.action
        return cls(ActionScales(float(action.translation_scale), float(action.pitch_scale)))

    def plan(self, facts: SceneFacts) -> list[Waypoint]:
        raise NotImplementedError

    def reset(self, env_ids, facts: list[SceneFacts]) -> None:
        """Plan the new episodes of the given envs."""
        for i, f in zip(env_ids, facts, strict=True):
            i = int(i)
            self.facts[i] = f
            self.note.pop(i, None)
            try:
                self.plans[i] = self.plan(f)
            except NoPlan as why:
                note = self.note[i] = f"{f.part_id}: {why}"
                self.plans[i] = []
                if note not in self._warned:
                    self._warned.add(note)
                    print(f"warning: {self.name} plans no motion on {note}", file=sys.stderr)
            self.phase[i] = self.count[i] = self.reached[i] = 0

    def step(self, i: int) -> str:
        """The name of env `i`'s current waypoint ("" while its episode has no plan)."""
        plan = self.plans.get(i)
        return plan[self.phase[i]].name if plan else ""

    def _act_one(self, i: int, obs: np.ndarray) -> np.ndarray:
        plan, facts = self.plans[i], self.facts[i]
        if not plan:  # nothing to do on this part: hold still, gripper open
            return _HOLD.copy()
        wp = plan[self.phase[i]]
        pos, _ = tcp_state(obs, facts)
        self.count[i] += 1
        if np.linalg.norm(pos - wp.pos) <= wp.tolerance:
            self.reached[i] += 1
        last = self.phase[i] == len(plan) - 1
        if not last and (self.reached[i] > wp.hold or self.count[i] >= wp.timeout):
            self.phase[i] += 1
            self.count[i] = self.reached[i] = 0
            wp = plan[self.phase[i]]
        return servo(obs, facts, wp, self.scales)


ARC_STEP = 0.03  # m of arc between two waypoints of a pull around a hinge


def opening_path(
    grasp: np.ndarray, facts: SceneFacts, distance: float, angle: float, wrist: float
) -> list[tuple[np.ndarray, float]]:
    """Where a point held on the front goes as it opens, with the hand's pitch change: straight
    along the opening direction for `distance` (m) on a slide; along its arc about the hinge for
    `angle` (rad) on a door or flap (a straight pull along the first tangent leaves the handle's
    path). The hinge axis of a flap, and of a door for the rolled hand, is the hand's pitch axis:
    the wrist turns by `wrist` times the front's turn, so the front does not turn into the
    fingers (a flap held level stalls at 43 deg); each policy sets the share per kind within
    the Panda's wrist joints 5 and 6 (`hook_oracle`: 0.3 on flaps, 1.0 on doors)."""
    if facts.joint_type == "slide":
        return [(grasp + distance * facts.pull_dir, 0.0)]
    axis = facts.hinge_axis / np.linalg.norm(facts.hinge_axis)
    turn = float(axis @ facts.tcp_nominal[:, 0])  # +-1 when the hinge is the pitch axis
    arm = grasp - facts.hinge_anchor
    radius = np.linalg.norm(arm - arm.dot(axis) * axis)
    steps = max(2, int(np.ceil(angle * radius / ARC_STEP)) + 1)
    return [
        (facts.hinge_anchor + rotated(arm, axis, theta), wrist * turn * theta)
        for theta in np.linspace(0.0, angle, steps)[1:]
    ]


def rotated(vector: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    """`vector` turned by `angle` (rad) about the unit `axis` (Rodrigues)."""
    c, s = np.cos(angle), np.sin(angle)
    return vector * c + np.cross(axis, vector) * s + axis * axis.dot(vector) * (1 - c)


def held_path(
    path: list[tuple[np.ndarray, float]], held: np.ndarray, tcp: np.ndarray, facts: SceneFacts
) -> list[tuple[np.ndarray, float]]:
    """An opening path of the point the hand holds (`held`, off the TCP) as the TCP's path: the
    hand keeps its offset to that point, turned by its own pitch change (about the TCP's x
    axis), so a fingertip hooked off the TCP follows its own arc whatever share of the front's
    turn the wrist follows (with the whole turn, the TCP's own arc)."""
    offset, x = tcp - held, facts.tcp_nominal[:, 0]
    return [(point + rotated(offset, x, turn), turn) for point, turn in path]


def follow(path: list[tuple[np.ndarray, float]], pitch: float, grip: float) -> list[Waypoint]:
    """Waypoints along an opening path (named "pull"): each passed once within 1 cm, the last
    held for good."""
    *through, (end, end_turn) = path
    return [
        *(Waypoint(p, pitch + t, grip, 0.01, timeout=10, name="pull") for p, t in through),
        Waypoint(end, pitch + end_turn, grip, tolerance=0.0, timeout=10**9, name="pull"),
    ]


@dataclass(frozen=True)
class Pull:
    """How a scripted policy pulls a front open (realikea/conf/policy/*.yaml: pull_*)."""

    distance: float = 0.4  # m along a drawer's opening direction
    angle: float = 1.2  # rad a door or flap is turned along its arc (success: 0.785)
    wrist: float = 0.3  # share of a hinged front's turn the wrist follows

    def path(self, grasp: np.ndarray, facts: SceneFacts) -> list[tuple[np.ndarray, float]]:
        return opening_path(grasp, facts, self.distance, self.angle, self.wrist)


def pull_waypoints(grasp: np.ndarray, pitch: float, facts: SceneFacts, pull: Pull = Pull()):
    """Close on the grasp, then pull along the front's opening path (`opening_path`)."""
    return [
        Waypoint(grasp, pitch, CLOSE, tolerance=1.0, hold=8, timeout=9),
        *follow(pull.path(grasp, facts), pitch, CLOSE),
    ]
