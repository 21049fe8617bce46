"""An exported URDF in PyBullet, with the joint resistance PyBullet does not apply by itself.

PyBullet reads a URDF joint's `<dynamics damping friction>` but uses only the damping (a force
-c v on the joint, the same as applying it by hand: `experiments/interop/results/pybullet.md`); the
friction is stored and ignored. Instead every joint gets a velocity motor of target 0 that holds
up to an impulse of 1 N s a step (500 N at 2 ms), which locks the front. Coulomb friction is
emulated here by that same motor with its force capped at the joint's friction: it cancels any
motion while the load is below the friction, and pushes back with exactly the friction when above.
PyBullet also damps every multibody it loads (linear and angular damping 0.04, mass-proportional,
which a URDF cannot set); `load_front` switches that off, since the MJCF has no such damping.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pybullet

from realikea.assets.library import FRONT_JOINT
from realikea.errors import RealIkeaError
from realikea.export.metadata import PART_LINK

GRAVITY = (0.0, 0.0, -9.81)  # MuJoCo's default, which the built MJCFs keep; cabinet frame +z up
PYBULLET_BODY_DAMPING = 0.04  # PyBullet's default linear and angular damping of a multibody
# how the front joint's friction is treated: emulated (a velocity motor capped at the URDF's
# friction), default (PyBullet's own velocity motor, as loaded) or ignored (no motor at all)
FRICTION_MODELS = ("emulated", "default", "ignored")
# how its damping is applied: by PyBullet from the URDF, by hand as a joint force -c v, or not at
# all (to measure what it does)
DAMPING_MODELS = ("urdf", "manual", "off")


@contextlib.contextmanager
def session(timestep: float, gravity=GRAVITY) -> Iterator[int]:
    """A headless PyBullet client with `timestep` and `gravity`, disconnected on exit."""
    client = pybullet.connect(pybullet.DIRECT)
    try:
        pybullet.setTimeStep(timestep, physicsClientId=client)
        pybullet.setGravity(*gravity, physicsClientId=client)
        yield client
    finally:
        pybullet.disconnect(client)


@dataclass(frozen=True)
class LoadedFront:
    """An exported configuration in a client: its body, the front's joint and the part's link."""

    client: int
    body: int
    joint: int  # the front joint's index (= the front link's)
    part: int  # the part link's index
    joint_type: str  # slide | hinge
    damping: float  # as PyBullet read it from <dynamics damping>
    friction: float  # as PyBullet read it from <dynamics friction>
    range: tuple[float, float]


def load_front(client: int, urdf: Path, body_damping: float = 0.0) -> LoadedFront:
    """Load an exported URDF with a fixed base, its multibody damping set to `body_damping`
    (none, as in MuJoCo; PYBULLET_BODY_DAMPING is PyBullet's own), and find its front joint
    and part link."""
    body = pybullet.loadURDF(str(urdf), useFixedBase=True, physicsClientId=client)
    pybullet.changeDynamics(
        body, -1, linearDamping=body_damping, angularDamping=body_damping, physicsClientId=client
    )
    infos = [
        pybullet.getJointInfo(body, i, physicsClientId=client)
        for i in range(pybullet.getNumJoints(body, physicsClientId=client))
    ]
    joints = {info[1].decode(): info for info in infos}
    links = {info[12].decode(): info[0] for info in infos}
    if FRONT_JOINT not in joints or PART_LINK not in links:
        raise RealIkeaError(f"{urdf}: no {FRONT_JOINT!r} joint or {PART_LINK!r} link")
    info = joints[FRONT_JOINT]
    kinds = {pybullet.JOINT_PRISMATIC: "slide", pybullet.JOINT_REVOLUTE: "hinge"}
    index, kind, damping, friction, lower, upper = (info[i] for i in (0, 2, 6, 7, 8, 9))
    return LoadedFront(
        client, body, index, links[PART_LINK], kinds[kind], damping, friction, (lower, upper)
    )


def set_friction(front: LoadedFront, model: str = "emulated") -> None:
    """Treat the front joint's friction as `model` (FRICTION_MODELS)."""
    if model not in FRICTION_MODELS:
        raise RealIkeaError(f"unknown friction model {model!r}; choose {FRICTION_MODELS}")
    if model == "default":
        return
    force = front.friction if model == "emulated" else 0.0
    pybullet.setJointMotorControl2(
        front.body,
        front.joint,
        pybullet.VELOCITY_CONTROL,
        targetVelocity=0.0,
        force=force,
        physicsClientId=front.client,
    )


def set_damping(front: LoadedFront, model: str = "urdf") -> None:
    """Leave the URDF damping to PyBullet (`urdf`), switch it off (`off`), or switch it off to
    apply it by hand (`manual`: call `manual_damping` before every step)."""
    if model not in DAMPING_MODELS:
        raise RealIkeaError(f"unknown damping model {model!r}; choose {DAMPING_MODELS}")
    if model != "urdf":
        pybullet.changeDynamics(
            front.body, front.joint, jointDamping=0.0, physicsClientId=front.client
        )


def manual_damping(front: LoadedFront) -> None:
    """Apply the damping force -c v to the front joint for the next step."""
    velocity = joint_state(front)[1]
    pybullet.setJointMotorControl2(
        front.body,
        front.joint,
        pybullet.TORQUE_CONTROL,
        force=-front.damping * velocity,
        physicsClientId=front.client,
    )


def joint_state(front: LoadedFront) -> tuple[float, float]:
    """The front joint's position and velocity (m, m/s or rad, rad/s)."""
    q, v = pybullet.getJointState(front.body, front.joint, physicsClientId=front.client)[:2]
    return float(q), float(v)


def link_pose(front: LoadedFront, link: int) -> tuple[np.ndarray, np.ndarray]:
    """World position and (x, y, z, w) quaternion of a link's URDF frame (not its inertia's)."""
    state = pybullet.getLinkState(
        front.body, link, computeForwardKinematics=True, physicsClientId=front.client
    )
    return np.asarray(state[4]), np.asarray(state[5])


def to_link(front: LoadedFront, link: int, point) -> np.ndarray:
    """A world point in a link's URDF frame, at the current pose."""
    pos, orn = link_pose(front, link)
    inv_pos, inv_orn = pybullet.invertTransform(pos, orn)
    return np.asarray(pybullet.multiplyTransforms(inv_pos, inv_orn, list(point), [0, 0, 0, 1])[0])


def to_world(front: LoadedFront, link: int, point) -> np.ndarray:
    """A point given in a link's URDF frame, in the world at the current pose."""
    pos, orn = link_pose(front, link)
    return np.asarray(pybullet.multiplyTransforms(pos, orn, list(point), [0, 0, 0, 1])[0])


def apply_force(front: LoadedFront, link: int, force, point) -> None:
    """Apply a world-frame force at a world point of a link for the next step (PyBullet clears
    external forces after every step)."""
    pybullet.applyExternalForce(
        front.body,
        link,
        [float(f) for f in force],
        [float(p) for p in point],
        pybullet.WORLD_FRAME,
        physicsClientId=front.client,
    )


def step(front: LoadedFront) -> None:
    """Advance the front's client by one physics step."""
    pybullet.stepSimulation(physicsClientId=front.client)
