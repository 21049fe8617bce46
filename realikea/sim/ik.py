"""Differential IK with mink: a TCP target (position + pitch) to a joint target for the arm.

One call = one QP (solver daqp) on a kinematic copy of the arm (no fingers, no contacts), so one
env step costs one call. Roll and yaw are fixed to the nominal TCP orientation; pitch turns the
nominal orientation about the world y axis (pitch > 0 tips the approach axis up). The QP tracks the
pose with a small posture term towards the home posture (the arm has one redundant degree of
freedom), stays inside the joint limits and moves no joint faster than its velocity limit over
the control period. The result is `ok` unless the QP fails, the target leaves the joint limits,
or the pose it reaches misses the target by more than the tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mink
import mujoco
import numpy as np
from omegaconf import DictConfig

from realikea.sim.robot import ARM_JOINTS, TCP_SITE, GripperModel, joint_limits, robot_xml

# Franka's joint velocity limits (rad/s).
VELOCITY_LIMIT = (2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61)
# The nominal TCP orientation in the world: approach (TCP z) along -x, into the cabinet front;
# finger motion (TCP y) along -z, so the jaws close vertically on a horizontal bar.
NOMINAL_TCP_ROTATION = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])

_KINEMATIC_GRIPPER = GripperModel("kinematic", 0.04, (0.0, 0.04), 0, 0, 0, 0, 0, 0.02, 1.0, 0)


def tcp_rotation(pitch: float, nominal: np.ndarray = NOMINAL_TCP_ROTATION) -> np.ndarray:
    """The TCP orientation for a pitch (rad): the nominal one turned about the world y axis."""
    c, s = math.cos(pitch), math.sin(pitch)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]) @ nominal


def tcp_pitch(rotation: np.ndarray, nominal: np.ndarray = NOMINAL_TCP_ROTATION) -> float:
    """The pitch (rad) of a TCP orientation: the world-y rotation angle from the nominal one."""
    rel = rotation @ nominal.T
    return math.atan2(rel[0, 2], rel[2, 2])


def yaw_quat(yaw: float) -> np.ndarray:
    return np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])


@dataclass(frozen=True)
class IKResult:
    """A joint target for the 7 arm actuators and how good it is."""

    q: np.ndarray  # (7,) joint target within the limits
    ok: bool
    position_error: float  # m between the target and the pose `q` reaches
    rotation_error: float  # rad


class IKController:
    """One differential-IK step per call, with its own kinematic copy of the arm."""

    def __init__(
        self,
        base_pos=(0.0, 0.0, 0.0),
        base_yaw: float = 0.0,
        home=None,
        dt: float = 0.1,
        position_tolerance: float = 0.005,
        rotation_tolerance: float = 0.05,
        posture_cost: float = 1e-3,
        damping: float = 1e-4,
        nominal: np.ndarray = NOMINAL_TCP_ROTATION,
        solver: str = "daqp",
    ):
        spec = mujoco.MjSpec.from_string(robot_xml(_KINEMATIC_GRIPPER, fingers=False))
        spec.body("link0").pos = np.asarray(base_pos, float)
        spec.body("link0").quat = yaw_quat(base_yaw)
        self.model = spec.compile()
        if self.model.nq != len(ARM_JOINTS):
            raise AssertionError("the kinematic arm model has exactly the 7 arm joints")
        self.configuration = mink.Configuration(self.model)
        self.frame = mink.FrameTask(TCP_SITE, "site", position_cost=1.0, orientation_cost=1.0)
        self.posture = mink.PostureTask(self.model, cost=posture_cost)
        self.home = np.zeros(7) if home is None else np.asarray(home, float)
        self.posture.set_target(self.home)
        self.limits = [
            mink.ConfigurationLimit(self.model),
            mink.VelocityLimit(self.model, dict(zip(ARM_JOINTS, VELOCITY_LIMIT, strict=True))),
        ]
        self.tasks = [self.frame, self.posture]
        self.dt, self.damping, self.solver = dt, damping, solver
        self.position_tolerance, self.rotation_tolerance = position_tolerance, rotation_tolerance
        self.nominal = np.asarray(nominal, float)
        self.bounds = joint_limits()
        self._site = self.model.site(TCP_SITE).id

    @classmethod
    def from_config(cls, cfg: DictConfig) -> IKController:
        """Built from the composed config: robot base pose, home posture and `sim.ik`."""
        robot, ik = cfg.sim.robot, cfg.sim.ik
        return cls(
            base_pos=tuple(robot.base_pos),
            base_yaw=math.radians(robot.base_yaw_deg),
            home=tuple(robot.home),
            dt=ik.dt,
            position_tolerance=ik.position_tolerance,
            rotation_tolerance=ik.rotation_tolerance,
            posture_cost=ik.posture_cost,
            damping=ik.damping,
            solver=ik.solver,
        )

    def tcp_pose(self, q) -> tuple[np.ndarray, np.ndarray]:
        """World TCP position (3,) and rotation (3, 3) at arm configuration q."""
        data = self.configuration.data
        data.qpos[:] = q
        mujoco.mj_kinematics(self.model, data)
        return data.site_xpos[self._site].copy(), data.site_xmat[self._site].reshape(3, 3).copy()

    def target(self, position, pitch: float) -> mink.SE3:
        rotation = tcp_rotation(pitch, self.nominal)
        return mink.SE3.from_rotation_and_translation(
            mink.SO3.from_matrix(rotation), np.asarray(position, float)
        )

    def solve(self, q, position, pitch: float) -> IKResult:
        """One QP from configuration q (7,) towards the TCP at `position` with `pitch`."""
        q = np.clip(np.asarray(q, float), self.bounds[:, 0], self.bounds[:, 1])
        self.configuration.update(q)
        target = self.target(position, pitch)
        self.frame.set_target(target)
        try:
            velocity = mink.solve_ik(
                self.configuration, self.tasks, self.dt, self.solver, damping=self.damping,
                limits=self.limits,
            )  # fmt: skip
        except mink.NoSolutionFound:
            return IKResult(q, False, math.inf, math.inf)
        q_new = self.configuration.integrate(velocity, self.dt)
        inside = bool(
            np.all(q_new >= self.bounds[:, 0] - 1e-6) and np.all(q_new <= self.bounds[:, 1] + 1e-6)
        )
        q_new = np.clip(q_new, self.bounds[:, 0], self.bounds[:, 1])
        pos, rot = self.tcp_pose(q_new)
        position_error = float(np.linalg.norm(pos - target.translation()))
        rel = rot.T @ target.rotation().as_matrix()
        rotation_error = float(np.arccos(np.clip((np.trace(rel) - 1) / 2, -1.0, 1.0)))
        ok = (
            inside
            and position_error <= self.position_tolerance
            and rotation_error <= self.rotation_tolerance
        )
        return IKResult(q_new, ok, position_error, rotation_error)
