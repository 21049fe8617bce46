"""A constant pull at the handle along its direction of opening, in MuJoCo on a built MJCF and in
PyBullet on its exported URDF: the front joint's opening step by step."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

from realikea.assets.library import load_model
from realikea.interop import pybullet_sim
from realikea.sim.resistance import lever_arm


@dataclass(frozen=True)
class Trajectory:
    """The front joint's position after each physics step (m or rad), from rest at 0."""

    timestep: float
    q: np.ndarray

    def at(self, seconds: float) -> float:
        """The opening after `seconds` (the last step at or before it)."""
        step = int(round(seconds / self.timestep))
        return float(self.q[min(max(step, 1), len(self.q)) - 1])

    def time_to(self, opening: float) -> float | None:
        """When the opening first reaches `opening` (s), or None if it never does."""
        reached = np.flatnonzero(self.q >= opening)
        return float((reached[0] + 1) * self.timestep) if len(reached) else None


def opening_direction(joint_type: str, anchor, axis, point) -> np.ndarray:
    """Unit direction in which `point` moves as the joint opens: the slide's axis, or the
    tangent of the hinge's circle through `point` (the axis rotated by a positive angle)."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    if joint_type == "slide":
        return axis
    tangent = np.cross(axis, np.asarray(point, float) - np.asarray(anchor, float))
    return tangent / np.linalg.norm(tangent)


def breakaway_force(joint_type: str, frictionloss: float, anchor, axis, handle) -> float:
    """The pull at the handle (N) that balances the joint's friction: the friction loss of a
    slide, friction loss / lever arm of a hinge (`realikea/sim/resistance.py`)."""
    if joint_type == "slide":
        return frictionloss
    return frictionloss / lever_arm(anchor, axis, handle)


def mujoco_pull(
    mjcf: Path, force: float, seconds: float = 1.0, timestep: float | None = None
) -> Trajectory:
    """`pull_at_handle` on a built MJCF; `timestep` replaces the model's own."""
    model = load_model(mjcf)
    if timestep is not None:
        model.opt.timestep = timestep
    return pull_at_handle(model, force, seconds)


def pull_at_handle(model: mujoco.MjModel, force: float, seconds: float = 1.0) -> Trajectory:
    """Pull a configuration's model at its `handle` site with `force` newtons along the site's
    direction of opening (following the front as it turns) for `seconds`."""
    data = mujoco.MjData(model)
    site, front = model.site("handle").id, model.body("front").id
    jac = np.zeros((3, model.nv))
    q = np.empty(int(round(seconds / model.opt.timestep)))
    for step in range(len(q)):
        mujoco.mj_forward(model, data)
        mujoco.mj_jacSite(model, data, jac, None, site)
        direction = jac[:, 0] / np.linalg.norm(jac[:, 0])
        data.qfrc_applied[:] = 0
        mujoco.mj_applyFT(
            model, data, force * direction, np.zeros(3), data.site_xpos[site], front,
            data.qfrc_applied,
        )  # fmt: skip
        mujoco.mj_step(model, data)
        q[step] = data.qpos[0]
    return Trajectory(float(model.opt.timestep), q)


def pybullet_pull(
    urdf: Path,
    handle,
    anchor,
    axis,
    force: float,
    seconds: float = 1.0,
    timestep: float = 0.002,
    friction: str = "emulated",
    damping: str = "urdf",
    body_damping: float = 0.0,
) -> Trajectory:
    """Pull an exported URDF in PyBullet at the handle (its world position with the front closed,
    carried on the part link) with `force` newtons along its direction of opening; the joint's
    `anchor` and `axis` (world, metadata.json's `joint`) give that direction. `friction`,
    `damping` and `body_damping` choose how PyBullet treats the resistance (`pybullet_sim`)."""
    with pybullet_sim.session(timestep) as client:
        front = pybullet_sim.load_front(client, urdf, body_damping)
        pybullet_sim.set_friction(front, friction)
        pybullet_sim.set_damping(front, damping)
        on_part = pybullet_sim.to_link(front, front.part, handle)
        q = np.empty(int(round(seconds / timestep)))
        for step in range(len(q)):
            point = pybullet_sim.to_world(front, front.part, on_part)
            direction = opening_direction(front.joint_type, anchor, axis, point)
            pybullet_sim.apply_force(front, front.part, force * direction, point)
            if damping == "manual":
                pybullet_sim.manual_damping(front)
            pybullet_sim.step(front)
            q[step] = pybullet_sim.joint_state(front)[0]
    return Trajectory(timestep, q)
