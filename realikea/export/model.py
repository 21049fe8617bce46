"""A built configuration read back from its MJCF as links, one joint, shapes and masses: what every
exporter writes (metres, kilograms, radians; the cabinet frame with the front closed).

Structure and masses come from MuJoCo's compiled model (body poses, the joint's range, masses
and inertias); each geom's pose and mesh file come from the XML, because MuJoCo recentres a
compiled mesh geom on its own centre of mass. The joint's damping and friction loss are the
library's nominal ones until `with_resistance` sets the exported mode.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, replace
from pathlib import Path

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation

from realikea.assets.cache import link_or_copy
from realikea.assets.library import FRONT_JOINT
from realikea.assets.workflow.assembly import SOLID_GROUP, VISUAL_GROUP, Joint
from realikea.errors import RealIkeaError
from realikea.sim.resistance import Resistance, handle_resistance, lever_arm

ROOT = "carcass"  # the one static link: every body welded to the world (the unit and the carcass)
JOINT_TYPES = {int(mujoco.mjtJoint.mjJNT_SLIDE): "slide", int(mujoco.mjtJoint.mjJNT_HINGE): "hinge"}


def pose_matrix(pos, quat_wxyz) -> np.ndarray:
    """The 4x4 transform of a position and a (w, x, y, z) quaternion."""
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_quat(np.roll(np.asarray(quat_wxyz, float), -1)).as_matrix()
    pose[:3, 3] = pos
    return pose


def quat_wxyz(pose: np.ndarray) -> np.ndarray:
    """The (w, x, y, z) quaternion of a 4x4 transform's rotation."""
    return np.roll(Rotation.from_matrix(pose[:3, :3]).as_quat(), 1)


@dataclass(frozen=True)
class Shape:
    """One geom in its link's frame: a box (half-extents) or a mesh file, seen and/or colliding."""

    name: str
    pose: np.ndarray
    half_extents: tuple[float, float, float] | None
    mesh: Path | None
    visual: bool
    collides: bool
    friction: float
    rgba: tuple[float, float, float, float]


@dataclass(frozen=True)
class Inertial:
    """A link's mass, its principal inertia frame (pose in the link frame) and moments."""

    mass: float
    pose: np.ndarray
    moments: tuple[float, float, float]


@dataclass(frozen=True)
class Link:
    """One rigid body: its world pose (front closed), its joint to `parent` (None: welded)."""

    name: str
    parent: str | None
    pose: np.ndarray
    joint: Joint | None
    shapes: list[Shape]
    inertial: Inertial


@dataclass(frozen=True)
class Articulation:
    """A configuration's links, the static root first and every parent before its children."""

    name: str
    mjcf: Path
    links: list[Link]
    handle: np.ndarray  # world position of the `handle` site

    @property
    def moving_link(self) -> Link:
        """The link the front's joint moves."""
        return next(link for link in self.links if link.joint is not None)

    def joint_anchor_axis(self) -> tuple[np.ndarray, np.ndarray]:
        """The front joint's anchor and unit axis in the cabinet frame."""
        link = self.moving_link
        rotation = link.pose[:3, :3]
        anchor = rotation @ np.asarray(link.joint.pos) + link.pose[:3, 3]
        return anchor, rotation @ np.asarray(link.joint.axis)

    def link(self, name: str) -> Link:
        return next(link for link in self.links if link.name == name)

    def mesh_files(self) -> list[Path]:
        """Every mesh file a shape uses, once each."""
        return list(dict.fromkeys(s.mesh for link in self.links for s in link.shapes if s.mesh))


def _shape(geom: ET.Element, body_pose: np.ndarray, meshes: dict[str, Path]) -> Shape:
    pos = [float(v) for v in geom.get("pos", "0 0 0").split()]
    quat = [float(v) for v in geom.get("quat", "1 0 0 0").split()]
    collides = not (geom.get("contype") == "0" and geom.get("conaffinity") == "0")
    group = int(geom.get("group", "0"))
    is_box = geom.get("type") == "box"
    return Shape(
        name=geom.get("name"),
        pose=body_pose @ pose_matrix(pos, quat),
        half_extents=tuple(float(v) for v in geom.get("size").split()) if is_box else None,
        mesh=None if is_box else meshes[geom.get("mesh")],
        visual=not collides or group in (SOLID_GROUP, VISUAL_GROUP),
        collides=collides,
        friction=float(geom.get("friction", "1").split()[0]),
        rgba=tuple(float(v) for v in geom.get("rgba", "0.5 0.5 0.5 1").split()),
    )


def _joint(model: mujoco.MjModel, body: int) -> Joint | None:
    if model.body_jntnum[body] == 0:
        return None
    j = model.body_jntadr[body]
    if model.body_jntnum[body] > 1 or int(model.jnt_type[j]) not in JOINT_TYPES:
        raise RealIkeaError(f"body {model.body(body).name!r}: only one slide or hinge is exported")
    dof = model.jnt_dofadr[j]
    return Joint(
        model.joint(j).name,
        JOINT_TYPES[int(model.jnt_type[j])],
        tuple(float(v) for v in model.jnt_pos[j]),  # anchor and unit axis in the link's frame
        tuple(float(v) for v in model.jnt_axis[j] / np.linalg.norm(model.jnt_axis[j])),
        (float(model.jnt_range[j][0]), float(model.jnt_range[j][1])),
        float(model.dof_damping[dof]),
        float(model.dof_frictionloss[dof]),
    )


def read_articulation(mjcf: Path) -> Articulation:
    """Read one built MJCF (model_coacd.xml or model_hull.xml) with the front closed."""
    mjcf = Path(mjcf)
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    tree = ET.parse(mjcf)
    meshes = {m.get("name"): mjcf.parent / m.get("file") for m in tree.iter("mesh")}
    geoms = {b.get("name"): b.findall("geom") for b in tree.iter("body")}
    root_shapes: list[Shape] = []
    links: list[Link] = []
    for b in range(1, model.nbody):
        name, world = model.body(b).name, pose_matrix(data.xpos[b], data.xquat[b])
        if model.body_weldid[b] == 0:  # static: its geoms join the root, posed in the world
            root_shapes += [_shape(g, world, meshes) for g in geoms[name]]
            continue
        parent = model.body_parentid[b]
        inertial = Inertial(
            float(model.body_mass[b]),
            pose_matrix(model.body_ipos[b], model.body_iquat[b]),
            tuple(float(v) for v in model.body_inertia[b]),
        )
        links.append(
            Link(
                name,
                ROOT if model.body_weldid[parent] == 0 else model.body(parent).name,
                world,
                _joint(model, b),
                [_shape(g, np.eye(4), meshes) for g in geoms[name]],
                inertial,
            )
        )
    joints = [link.joint.name for link in links if link.joint is not None]
    if joints != [FRONT_JOINT]:
        raise RealIkeaError(f"{mjcf}: expected one joint, {FRONT_JOINT!r}; found {joints}")
    root = Link(ROOT, None, np.eye(4), None, root_shapes, Inertial(0.0, np.eye(4), (0.0, 0.0, 0.0)))
    name = tree.getroot().get("model")
    return Articulation(name, mjcf, [root, *links], data.site("handle").xpos.copy())


def link_mesh_files(articulation: Articulation, folder: Path) -> dict[Path, str]:
    """Put every mesh the articulation uses into `folder` at the same path relative to its MJCF
    (hard-linked like the library's own meshes, copied across file systems); returns each source
    file's relative path (POSIX), for the written model to reference."""
    relative = {}
    for source in articulation.mesh_files():
        rel = source.relative_to(articulation.mjcf.parent)
        link_or_copy(source, folder / rel)
        relative[source] = rel.as_posix()
    return relative


def with_resistance(articulation: Articulation, mode: Resistance) -> Articulation:
    """The articulation with its front joint at one resistance mode, a hinge's scaled to its
    handle's lever arm as the scene scales it (`realikea/sim/resistance.py`)."""
    link = articulation.moving_link
    anchor, axis = articulation.joint_anchor_axis()
    lever = lever_arm(anchor, axis, articulation.handle) if link.joint.type == "hinge" else 0.0
    damping, frictionloss = handle_resistance(
        link.joint.type, lever, mode.damping, mode.frictionloss
    )
    joint = replace(link.joint, damping=damping, frictionloss=frictionloss)
    links = [replace(x, joint=joint) if x is link else x for x in articulation.links]
    return replace(articulation, links=links)
