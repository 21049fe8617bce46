"""Scripted policies as waypoint plans: servo the TCP through poses, then pull along the front.

A plan is made per episode from the scene's `SceneFacts`; `act` turns the current waypoint into
the task's 5-D action (the same action a learned policy emits, saturated at the task's scales).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from realikea.policies.per_env import PerEnvPolicy
from realikea.sim.ik import tcp_pitch
from realikea.tasks import observations
from realikea.tasks.facts import SceneFacts
from realikea.tasks.open_task import ACTION_SIZE

OPEN, CLOSE = 1.0, -1.0  # gripper commands (a4)
_SLICES = observations.slices()


@dataclass(frozen=True)
class Waypoint:
    """Hold the TCP at `pos` (world) with `pitch` and gripper command `grip`.

    The waypoint is done once the TCP is within `tolerance` (m) and `hold` more steps have
    passed, or after `timeout` steps whatever happens.
    """

    pos: np.ndarray
    pitch: float
    grip: float
    tolerance: float = 0.005
    hold: int = 0
    timeout: int = 40


@dataclass(frozen=True)
class ActionScales:
    """The task's action scales (conf/task/open.yaml: action)."""

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
            self.facts[i], self.plans[i] = f, self.plan(f)
            self.phase[i] = self.count[i] = self.reached[i] = 0

    def _act_one(self, i: int, obs: np.ndarray) -> np.ndarray:
        plan, facts = self.plans[i], self.facts[i]
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


def pull_waypoints(grasp: np.ndarray, pitch: float, facts: SceneFacts, distance: float = 0.4):
    """Close on the grasp, then a linear pull along the opening direction at the grasp."""
    return [
        Waypoint(grasp, pitch, CLOSE, tolerance=1.0, hold=8, timeout=9),
        Waypoint(grasp + distance * facts.pull_dir, pitch, CLOSE, tolerance=0.0, timeout=10**9),
    ]
