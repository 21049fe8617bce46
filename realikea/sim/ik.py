"""Differential IK with mink: a TCP target (position + pitch) to a joint target for the arm.

One call = one QP (solver daqp) on a kinematic copy of the arm (no fingers, no contacts), so one
env step costs one call. Roll and yaw are fixed to the nominal TCP orientation; pitch turns the
nominal orientation about the world y axis (pitch > 0 tips the approach axis up). The QP tracks the
pose with a small posture term towards the home posture (the arm has one redundant degree of
freedom), stays inside the joint limits and moves no joint faster than its velocity limit over
the control period. The result is `ok` unless the QP fails, the target leaves the joint limits,
or the pose it reaches misses the target by more than the tolerance.

The QP is mink's (`mink.solve_ik` with these tasks and limits, solver daqp), assembled in place:
mink's FrameTask computes the TCP error and Jacobian, the posture term and the box constraints
(their structure is fixed) live in preallocated arrays, and daqp gets the same matrices in the same
order as through mink and qpsolvers, so the solution is the same to the last bit
(tests/test_robot.py checks it against `mink.solve_ik`) at a fraction of the Python overhead.
"""

from __future__ import annotations

import math
from ctypes import c_int
from dataclasses import dataclass

import daqp
import mink
import mujoco
import numpy as np
from omegaconf import DictConfig

from realikea.errors import RealIkeaError
from realikea.sim.robot import ARM_JOINTS, TCP_SITE, GripperModel, joint_limits, robot_xml

# Franka's joint velocity limits (rad/s).
VELOCITY_LIMIT = (2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61)
# The nominal TCP orientation in the world: approach (TCP z) along -x, into the cabinet front;
# finger motion (TCP y) along -z, so the jaws close vertically on a horizontal bar.
NOMINAL_TCP_ROTATION = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])

_KINEMATIC_GRIPPER = GripperModel("kinematic", 0.04, (0.0, 0.04), 0, 0, 0, 0, 0, 0.02, 1.0, 0)


def rolled_nominal(roll: float) -> np.ndarray:
    """The nominal TCP orientation turned by `roll` (rad) about the approach axis (world -x).

    A configuration's handle mounted with roll r (a vertical bar on a door: 90 deg) gets the hand
    rolled by r, so the jaws close across the bar as they do on a drawer's horizontal bar.
    """
    c, s = math.cos(roll), math.sin(roll)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ NOMINAL_TCP_ROTATION


def tcp_rotation(pitch: float, nominal: np.ndarray = NOMINAL_TCP_ROTATION) -> np.ndarray:
    """The TCP orientation for a pitch (rad): the nominal one turned about its own x axis (the
    axis across both the approach and the jaw motion; world y for the unrolled hand)."""
    c, s = math.cos(pitch), math.sin(pitch)
    return nominal @ np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def tcp_pitch(rotation: np.ndarray, nominal: np.ndarray = NOMINAL_TCP_ROTATION) -> float:
    """The pitch (rad) of a TCP orientation: its rotation about the nominal's x axis."""
    rel = nominal.T @ rotation
    return math.atan2(rel[2, 1], rel[1, 1])


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
        if solver != "daqp":
            raise RealIkeaError(f"the IK hands its QP to daqp directly, got solver={solver!r}")
        spec = mujoco.MjSpec.from_string(
            robot_xml(_KINEMATIC_GRIPPER, fingers=False, visuals=False)
        )
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
        self._lower, self._upper = self.bounds[:, 0].copy(), self.bounds[:, 1].copy()
        # the limits with a 1e-6 rad tolerance, as lists: 7 float comparisons beat 4 numpy calls
        self._inside_bounds = ((self._lower - 1e-6).tolist(), (self._upper + 1e-6).tolist())
        self._qp = _ArmQP(self.configuration, self.frame, self.posture, self.limits, dt, damping)
        self._target = mink.SE3(wxyz_xyz=np.zeros(7))
        self._target.wxyz_xyz[0] = 1.0
        self.frame.set_target(self._target)
        self._target = self.frame.transform_target_to_world  # set_target copies; fill this one

    @classmethod
    def from_config(
        cls, cfg: DictConfig, nominal=NOMINAL_TCP_ROTATION, home=None, base_pos=None
    ) -> IKController:
        """Built from the composed config: robot base pose, home posture and `sim.ik` (a rolled
        hand passes its own nominal orientation and home posture; a scene that placed the robot
        passes its base position)."""
        robot, ik = cfg.sim.robot, cfg.sim.ik
        return cls(
            base_pos=tuple(robot.base_pos if base_pos is None else base_pos),
            base_yaw=math.radians(robot.base_yaw_deg),
            home=tuple(robot.home) if home is None else tuple(home),
            dt=ik.dt,
            position_tolerance=ik.position_tolerance,
            rotation_tolerance=ik.rotation_tolerance,
            posture_cost=ik.posture_cost,
            damping=ik.damping,
            nominal=nominal,
            solver=ik.solver,
        )

    def converge(self, q, position, pitch: float, steps: int = 200) -> np.ndarray:
        """Repeat IK steps from q until the pose is reached to 0.1 mm and 1 mrad (e.g. a rolled
        home posture); the posture term's slow null-space drift is not waited for."""
        q = np.asarray(q, float)
        for _ in range(steps):
            result = self.solve(q, position, pitch)
            if result.ok and result.position_error < 1e-4 and result.rotation_error < 1e-3:
                return result.q
            q = result.q
        raise RealIkeaError(
            f"IK did not reach {np.round(position, 3).tolist()} at pitch {pitch} "
            f"in {steps} steps (residual {result.position_error:.4f} m, "
            f"{result.rotation_error:.3f} rad)"
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
        lower, upper = self._lower, self._upper
        q = np.minimum(np.maximum(q, lower), upper)  # np.clip's result, without its overhead
        rotation = tcp_rotation(pitch, self.nominal)
        target = self._target.wxyz_xyz  # what mink.SE3.from_rotation_and_translation builds
        mujoco.mju_mat2Quat(target[:4], rotation.ravel())
        target[4:] = position
        q_new = self._qp.step(q)
        if q_new is None:
            return IKResult(q, False, math.inf, math.inf)
        lows, highs = self._inside_bounds
        inside = all(lo <= x <= hi for x, lo, hi in zip(q_new.tolist(), lows, highs, strict=True))
        q_new = np.minimum(np.maximum(q_new, lower), upper)
        # the pose q_new reaches: forward kinematics only, on the IK's own data
        data = self.configuration.data
        data.qpos[:] = q_new
        mujoco.mj_kinematics(self.model, data)
        offset = data.site_xpos[self._site] - target[4:]
        position_error = math.sqrt(offset @ offset)  # np.linalg.norm's arithmetic
        # rotation angle between the reached and the target orientation: trace(R^T R_target)
        cos = (float(np.vdot(data.site_xmat[self._site], rotation)) - 1.0) / 2.0
        rotation_error = math.acos(min(max(cos, -1.0), 1.0))
        ok = (
            inside
            and position_error <= self.position_tolerance
            and rotation_error <= self.rotation_tolerance
        )
        return IKResult(q_new, ok, position_error, rotation_error)


class _ArmQP:
    """The QP of `mink.solve_ik(configuration, [frame, posture], dt, "daqp", damping, limits)`
    for the 7-joint arm, built the way mink.build_ik builds it but into preallocated arrays.

    Objective: W = [frame's weighted Jacobian; posture's (a constant diagonal)], e likewise,
    H = W^T W + (damping + mu) I, c = -(e W). Constraints (ConfigurationLimit, VelocityLimit,
    in that order): G = [P; -P; P_v; -P_v], h = [gain (q_max - q); gain (q - q_min); dt v; dt v].
    The solution goes through daqp exactly as qpsolvers passes it (blower -1e30, all
    inequalities) and is integrated as mink.Configuration.integrate does.
    """

    def __init__(self, configuration, frame, posture, limits, dt: float, damping: float):
        model = configuration.model
        nv = model.nv
        config_limit, velocity_limit = limits
        if not (
            isinstance(config_limit, mink.ConfigurationLimit)
            and isinstance(velocity_limit, mink.VelocityLimit)
            and len(config_limit.indices) == nv
            and len(velocity_limit.indices) == nv
            and posture.lm_damping == 0.0
            and frame.lm_damping == 0.0
            and frame.gain == 1.0
            and np.all(frame.cost == 1.0)
            and not np.any(model.jnt_type != mujoco.mjtJoint.mjJNT_HINGE)
        ):
            raise AssertionError("_ArmQP is built for the arm's hinge joints, tasks and limits")
        self.configuration, self.frame, self.posture = configuration, frame, posture
        self.model, self.data = model, configuration.data
        self.dt, self.damping = dt, damping
        self.W = np.zeros((6 + nv, nv))
        self.W[6:] = posture.cost[:, None] * np.eye(nv)  # PostureTask: Jacobian I, cost-weighted
        self.e = np.empty(6 + nv)
        self.posture_scale = posture.cost * -posture.gain
        self.home = posture.target_q
        p, pv = config_limit.projection_matrix, velocity_limit.projection_matrix
        self.G = np.vstack([p, -p, pv, -pv])
        self.h = np.empty(4 * nv)
        self.h[2 * nv : 3 * nv] = dt * velocity_limit.limit
        self.h[3 * nv :] = dt * velocity_limit.limit
        self.gain, self.lower, self.upper = (
            config_limit.gain,
            config_limit.lower,
            config_limit.upper,
        )
        self.blower = np.full(4 * nv, -1e30)
        self.sense = np.zeros(4 * nv, dtype=c_int)
        self.damping_eye = (damping + 0.0) * np.eye(nv)  # mink adds damping + sum of task mu

    def step(self, q: np.ndarray) -> np.ndarray | None:
        """The configuration one QP step from q (within the joint limits), None if daqp fails."""
        model, data, nv = self.model, self.data, self.model.nv
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)  # what mink.Configuration.update runs (no equalities)
        mujoco.mj_comPos(model, data)
        W, e, h = self.W, self.e, self.h
        W[:6], e[:6], _ = self.frame.compute_qp_residual(self.configuration)
        e[6:] = self.posture_scale * (q - self.home)
        H = W.T @ W
        H += self.damping_eye  # the LM damping on the diagonal (the tasks add no mu)
        c = -(e @ W)
        h[:nv] = self.gain * (self.upper - q)
        h[nv : 2 * nv] = self.gain * (q - self.lower)
        x, _, exitflag, _ = daqp.solve(H, c, self.G, h, self.blower, self.sense)
        if exitflag <= 0:
            return None
        q_new = q.copy()
        mujoco.mj_integratePos(model, q_new, x / self.dt, self.dt)
        return q_new
