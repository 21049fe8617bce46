"""The task scene: the robot in front of one built configuration, on a floor, with lights.

World frame: the floor is z = 0; x = 0 is the cabinet's front plane, +x points out of the front
towards the robot, +y to the viewer's right (the configuration's own frame, raised to where it
stands). Two scenes (`cfg.scene`, realikea/conf/scene/):

* `kitchen` (default): the configuration stands in a fitted kitchen run (realikea/sim/kitchen.py)
  on the floor, and the robot is placed as a mobile manipulator with a lift would be: facing the
  handle from `scene.robot.standoff`, its base `scene.robot.handle_above_base` below the handle
  within the lift's range, or as a `scene.robot.placements` entry for the configuration's
  category and kind says, with the arm's home posture for that placement.
* `freestanding`: the configuration alone on a plinth whose height depends on the base kind, the
  robot on the floor at `sim.robot.base_pos` (the layout every result before the kitchen used).

The configuration is attached with the prefix `cabinet/`; which collision source it uses is only
which MJCF is passed. The front joint's resistance is the mode's (`cfg.resistance`), scaled on
hinges to the handle's lever arm (realikea/sim/resistance.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
from omegaconf import DictConfig

from realikea.errors import RealIkeaError
from realikea.sim.ik import yaw_quat
from realikea.sim.kitchen import add_kitchen, read_unit
from realikea.sim.resistance import Resistance, handle_resistance, lever_arm
from realikea.sim.robot import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    FINGER_JOINTS,
    GRIPPER_ACTUATOR,
    PAD_GEOMS,
    TCP_SITE,
    GripperModel,
    joint_limits,
    robot_xml,
)

PREFIX = "cabinet/"
FRONT_JOINT = PREFIX + "front_joint"
HANDLE_SITE = PREFIX + "handle"
FRONT_BODY = PREFIX + "front"
PART_BODY = PREFIX + "part"
CABINET_ROOT = PREFIX + "unit"
__all__ = [
    "ARM_ACTUATORS",
    "ARM_JOINTS",
    "CABINET_ROOT",
    "FINGER_JOINTS",
    "FRONT_BODY",
    "PART_BODY",
    "FRONT_JOINT",
    "GRIPPER_ACTUATOR",
    "HANDLE_SITE",
    "PAD_GEOMS",
    "TCP_SITE",
    "build_scene",
    "reset_home",
]

_CONES = {"elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC, "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL}
_INTEGRATORS = {
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
}


def _look_at(pos, target) -> np.ndarray:
    """Quaternion of a camera at `pos` looking at `target` with the world z axis up."""
    z = np.asarray(pos, float) - np.asarray(target, float)
    z /= np.linalg.norm(z)
    x = np.cross([0.0, 0.0, 1.0], z)
    x /= np.linalg.norm(x)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.column_stack([x, np.cross(z, x), z]).ravel())
    return quat


def _skeleton(cfg: DictConfig, visuals: bool = True) -> mujoco.MjSpec:
    """The robot on the floor with lights and the physics options of the config."""
    sim = cfg.sim
    gripper = GripperModel.from_config(cfg.gripper)
    spec = mujoco.MjSpec.from_string(
        robot_xml(gripper, command_filter=float(sim.robot.command_filter), visuals=visuals)
    )
    base = spec.body("link0")
    base.pos = np.asarray(sim.robot.base_pos, float)
    base.quat = yaw_quat(math.radians(sim.robot.base_yaw_deg))
    opt = spec.option
    opt.timestep = float(sim.timestep)
    if sim.integrator not in _INTEGRATORS:
        raise RealIkeaError(f"sim.integrator must be one of {sorted(_INTEGRATORS)}")
    opt.integrator = _INTEGRATORS[sim.integrator]
    if cfg.contact.cone not in _CONES:
        raise RealIkeaError(f"contact.cone must be one of {sorted(_CONES)}")
    opt.cone = _CONES[cfg.contact.cone]
    opt.impratio = float(cfg.contact.impratio)
    opt.noslip_iterations = int(cfg.contact.noslip_iterations)
    world = spec.worldbody
    world.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[3, 3, 0.05],
        rgba=[0.55, 0.55, 0.52, 1], friction=[float(sim.floor_friction), 0.005, 0.0001],
    )  # fmt: skip
    world.add_light(name="key", pos=[1.5, 1.0, 2.5], dir=[-0.5, -0.3, -1], castshadow=False)
    world.add_light(name="fill", pos=[1.0, -1.5, 2.0], dir=[-0.3, 0.6, -1], castshadow=False)
    spec.visual.global_.offwidth = 640
    spec.visual.global_.offheight = 480
    return spec


def _plinth(cabinet: mujoco.MjSpec, height: float) -> None:
    """A box under the carcass (the cabinet's legs and kick plate), if it is raised; part of the
    cabinet's root body, so base pose randomization moves it with the carcass."""
    if height <= 0:
        return
    bottom = cabinet.geom("carcass_bottom")
    side = cabinet.geom("carcass_side_left")
    if bottom is None or side is None:
        raise RealIkeaError("the configuration has no carcass_bottom / carcass_side_left geom")
    half = [float(bottom.size[0]), abs(float(side.pos[1])) + float(side.size[1]), height / 2]
    cabinet.body(CABINET_ROOT.removeprefix(PREFIX)).add_geom(
        name="plinth", type=mujoco.mjtGeom.mjGEOM_BOX, size=half,
        pos=[float(bottom.pos[0]), 0.0, -height / 2], rgba=[0.3, 0.3, 0.3, 1],
    )  # fmt: skip


def base_kind(cabinet: mujoco.MjSpec) -> str:
    """drawer, door or flap, from the configuration's front joint (slide, vertical or
    horizontal hinge)."""
    joint = cabinet.joint("front_joint")
    if joint is None:
        raise RealIkeaError("the configuration has no joint named front_joint")
    if joint.type == mujoco.mjtJoint.mjJNT_SLIDE:
        return "drawer"
    return "door" if abs(joint.axis[2]) > 0.5 else "flap"


@dataclass(frozen=True)
class ClosedFront:
    """The configuration's handle and front joint with the front closed (cabinet frame)."""

    handle: np.ndarray  # (3,) the handle site
    joint_type: str  # slide or hinge
    lever: float  # m from the hinge axis to the handle (0 for a slide)


def closed_front(config_mjcf: Path) -> ClosedFront:
    """The handle and the front's joint, from the configuration compiled on its own."""
    model = mujoco.MjModel.from_xml_path(str(config_mjcf))
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    handle = data.site("handle").xpos.copy()
    joint = model.joint("front_joint").id
    if model.jnt_type[joint] == mujoco.mjtJoint.mjJNT_SLIDE:
        return ClosedFront(handle, "slide", 0.0)
    return ClosedFront(handle, "hinge", lever_arm(data.xanchor[joint], data.xaxis[joint], handle))


@dataclass(frozen=True)
class Placement:
    """How far below the handle the kitchen's lift puts the arm's base, the arm's home posture
    there, and whether the hand is turned half a turn about its approach from the roll the task
    picks (`hand_turned`: the way its wrist pitches is then reversed)."""

    handle_above_base: float  # m
    home: np.ndarray  # (7,) rad
    hand_turned: bool = False


_PLACEMENT_KEYS = {"category", "kind", "handle_above_base", "home"}  # every entry names them


def placement(cfg: DictConfig, category: str | None, kind: str) -> Placement:
    """The kitchen robot's placement for a configuration of this part category and base kind:
    the `scene.robot.placements` entry naming both, else `scene.robot.handle_above_base` with
    `sim.robot.home`. Outside the kitchen, the home posture only (the height is unused)."""
    robot = cfg.scene.get("robot")
    default = Placement(float(robot.handle_above_base) if robot else 0.0,
                        np.asarray(cfg.sim.robot.home, float))  # fmt: skip
    if cfg.scene.name != "kitchen":
        return default
    found = default
    lo, hi = joint_limits().T
    for i, entry in enumerate(robot.get("placements") or []):
        where = f"scene.robot.placements[{i}]"
        missing = _PLACEMENT_KEYS - set(entry)
        if missing:
            raise RealIkeaError(f"{where} lacks {', '.join(sorted(missing))}")
        unknown = set(entry) - _PLACEMENT_KEYS - {"hand_turned"}
        if unknown:
            raise RealIkeaError(f"{where} has unknown keys {', '.join(sorted(unknown))}; known: "
                                f"{', '.join(sorted(_PLACEMENT_KEYS))}, hand_turned")  # fmt: skip
        turned = entry.get("hand_turned", False)
        if not isinstance(turned, bool):
            raise RealIkeaError(f"{where}.hand_turned={turned!r}: true or false, please")
        home = np.asarray(entry.home, float)
        if home.shape != (7,) or np.any(home < lo) or np.any(home > hi):
            raise RealIkeaError(f"{where}.home={list(entry.home)}: seven angles within the arm's "
                                "joint limits, please")  # fmt: skip
        if entry.category == category and entry.kind == kind and found is default:
            found = Placement(float(entry.handle_above_base), home, turned)
    return found


def robot_base(scene: DictConfig, handle: np.ndarray, sim: DictConfig, above: float) -> np.ndarray:
    """Where the robot's base stands: at `sim.robot.base_pos` in the freestanding scene; in the
    kitchen facing the handle (world frame) from the stand-off, raised by the lift to `above`
    below it (`placement`), within the lift's range."""
    if scene.name != "kitchen":
        return np.asarray(sim.robot.base_pos, float)
    robot = scene.robot
    lo, hi = (float(v) for v in robot.lift)
    height = min(max(float(handle[2]) - above, lo), hi)
    return np.array([float(handle[0]) + float(robot.standoff), float(handle[1]), height])


def _platform(spec: mujoco.MjSpec, base: np.ndarray) -> None:
    """The lift column under a raised robot base (visual: nothing reaches under the arm)."""
    if base[2] <= 0.005:
        return
    spec.worldbody.add_geom(
        name="lift_column", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.09, 0.09, base[2] / 2],
        pos=[base[0] + 0.02, base[1], base[2] / 2], rgba=[0.35, 0.37, 0.4, 1],
        contype=0, conaffinity=0, group=1,
    )  # fmt: skip


def build_scene(
    config_mjcf: Path, cfg: DictConfig, place: Placement | None = None, visuals: bool = True
) -> mujoco.MjModel:
    """Compile the robot (cfg.gripper) in front of one configuration (cfg.resistance applied to
    its front joint) in cfg.scene, with the contact model of cfg.contact and cfg.sim's physics;
    `place` (the part's `placement`; by default the one naming no category) sets the kitchen
    robot's height below the handle. `visuals` draws the robot as the Panda's meshes (robot_xml;
    the same dynamics either way). The configuration's meshes stay relative to its own MJCF
    (MuJoCo resolves them from that file's folder); the robot's are absolute paths."""
    config_mjcf = Path(config_mjcf)
    if not config_mjcf.is_file():
        raise RealIkeaError(f"MJCF not found: {config_mjcf}")
    spec = _skeleton(cfg, visuals)
    cabinet = mujoco.MjSpec.from_file(str(config_mjcf))
    # the parent's options rule; copying them avoids MuJoCo's attach-conflict warning
    cabinet.option.cone, cabinet.option.impratio = spec.option.cone, spec.option.impratio
    cabinet.option.timestep = spec.option.timestep
    for light in cabinet.lights:
        cabinet.delete(light)
    kind, scene = base_kind(cabinet), cfg.scene
    if scene.name == "kitchen":
        height = add_kitchen(cabinet, read_unit(cabinet, kind), scene)
    else:
        plinth = scene.plinth_height  # one height, or one per base kind
        height = float(plinth[kind] if isinstance(plinth, DictConfig) else plinth)
        _plinth(cabinet, height)
    frame = spec.worldbody.add_frame(pos=[0.0, 0.0, height])
    spec.attach(cabinet, prefix=PREFIX, frame=frame)
    front = closed_front(config_mjcf)
    handle = front.handle + [0.0, 0.0, height]  # in the world
    place = placement(cfg, None, kind) if place is None else place
    base = robot_base(scene, handle, cfg.sim, place.handle_above_base)
    spec.body("link0").pos = base
    _platform(spec, base)
    eye = handle + np.array([1.35, -1.3, 0.95])  # the overview camera, aimed at the handle
    spec.worldbody.add_camera(name="overview", pos=eye, quat=_look_at(eye, handle + [0.22, 0, 0]))
    joint = spec.joint(FRONT_JOINT)
    mode = Resistance.from_config(cfg)
    damping_value, friction_value = handle_resistance(
        front.joint_type, front.lever, mode.damping, mode.frictionloss
    )
    damping = np.array(joint.damping, dtype=float, ndmin=1)  # MuJoCo 4: polynomial coefficients
    damping[0] = damping_value
    joint.damping = damping if np.ndim(joint.damping) else float(damping[0])
    joint.frictionloss = friction_value
    try:
        model = spec.compile()
    except ValueError as err:
        raise RealIkeaError(f"{config_mjcf}: the scene does not compile: {err}") from err
    cap_front_friction(model, float(cfg.gripper.pad_friction))
    return model


def cap_front_friction(model: mujoco.MjModel, pad_friction: float) -> None:
    """Cap the sliding friction of the moving front's geoms (the part and the panel) at the
    pads': MuJoCo uses the larger coefficient of a contact's two geoms, so without the cap a
    pad of 0.3 on a part of 0.6 would slide at 0.6. The presets' pads (1.0) are above every
    front geom, so for them nothing changes."""
    geoms = subtree_geoms(model, model.body(FRONT_BODY).id)
    model.geom_friction[geoms, 0] = np.minimum(model.geom_friction[geoms, 0], pad_friction)


def subtree_geoms(model: mujoco.MjModel, body: int) -> list[int]:
    """The geoms of `body` and of every body below it (what moves with a front's joint)."""
    inside = np.zeros(model.nbody, bool)
    inside[body] = True
    for b in range(body + 1, model.nbody):  # MuJoCo numbers a parent before its children
        inside[b] = inside[model.body_parentid[b]]
    return np.flatnonzero(inside[model.geom_bodyid]).tolist()


def reset_home(model: mujoco.MjModel, data: mujoco.MjData, cfg: DictConfig, home=None) -> None:
    """Reset to the home posture (cfg's, or the given one) with the gripper open and the front
    closed."""
    mujoco.mj_resetData(model, data)
    gripper = GripperModel.from_config(cfg.gripper)
    home = np.asarray(cfg.sim.robot.home if home is None else home, float)
    for name, value in zip(ARM_JOINTS, home, strict=True):
        data.qpos[model.jnt_qposadr[model.joint(name).id]] = value
    for name in FINGER_JOINTS:
        data.qpos[model.jnt_qposadr[model.joint(name).id]] = gripper.stroke
    for name, value in zip(ARM_ACTUATORS, home, strict=True):
        actuator = model.actuator(name).id
        data.ctrl[actuator] = value
        if model.actuator_actadr[actuator] >= 0:  # the filtered command starts at home too
            data.act[model.actuator_actadr[actuator]] = value
    data.ctrl[model.actuator(GRIPPER_ACTUATOR).id] = gripper.ctrl(1.0)
    mujoco.mj_forward(model, data)
