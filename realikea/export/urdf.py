"""URDF: one link per rigid body, one <collision> per convex piece, the visual mesh apart, metres.

A URDF link's frame is its joint's frame and a joint turns about its frame's origin, so a link
whose MuJoCo joint is anchored off its body origin (a hinge on the front's edge) is written in
the body's frame moved to the anchor, and its shapes and inertia are moved back by as much.
"""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from realikea.export.model import Articulation, Link, link_mesh_files

URDF_JOINT = {"slide": "prismatic", "hinge": "revolute"}
# URDF requires an effort and a velocity limit on a moving joint; nothing drives this one (a
# passive front), so they are set far above anything a hand applies (N or N m; m/s or rad/s)
PASSIVE_EFFORT = 1000.0
PASSIVE_VELOCITY = 10.0
RESISTANCE_SCHEMA = (
    "URDF <joint><dynamics damping friction/>: MuJoCo's damping and frictionloss as built "
    "(prismatic: N s/m and N; revolute: N m s/rad and N m)"
)


def _fmt(values) -> str:
    return " ".join(f"{float(v):.9g}" for v in values)


def _origin(parent: ET.Element, pose: np.ndarray, tag: str = "origin") -> None:
    with warnings.catch_warnings():  # at +-90 deg pitch any split of roll and yaw is exact
        warnings.simplefilter("ignore", UserWarning)
        rpy = Rotation.from_matrix(pose[:3, :3]).as_euler("xyz")  # fixed axes: roll-pitch-yaw
    ET.SubElement(parent, tag, xyz=_fmt(pose[:3, 3]), rpy=_fmt(rpy))


def _frame(link: Link) -> np.ndarray:
    """The URDF frame of a link in the world: its body frame, moved onto its joint's anchor."""
    frame = link.pose.copy()
    if link.joint is not None:
        frame[:3, 3] = link.pose[:3, :3] @ np.asarray(link.joint.pos) + link.pose[:3, 3]
    return frame


def _link(robot: ET.Element, link: Link, frame: np.ndarray, files: dict[Path, str]) -> None:
    node = ET.SubElement(robot, "link", name=link.name)
    to_frame = np.linalg.inv(frame) @ link.pose  # body frame -> URDF link frame
    inertial = ET.SubElement(node, "inertial")
    _origin(inertial, to_frame @ link.inertial.pose)
    ET.SubElement(inertial, "mass", value=f"{link.inertial.mass:.9g}")
    ixx, iyy, izz = (f"{m:.9g}" for m in link.inertial.moments)
    ET.SubElement(inertial, "inertia", ixx=ixx, iyy=iyy, izz=izz, ixy="0", ixz="0", iyz="0")
    for shape in link.shapes:
        roles = [r for r, on in (("visual", shape.visual), ("collision", shape.collides)) if on]
        for role in roles:
            element = ET.SubElement(node, role, name=shape.name)
            _origin(element, to_frame @ shape.pose)
            geometry = ET.SubElement(element, "geometry")
            if shape.mesh is None:
                ET.SubElement(geometry, "box", size=_fmt(2 * np.asarray(shape.half_extents)))
            else:
                ET.SubElement(geometry, "mesh", filename=files[shape.mesh])
            if role == "visual":
                material = ET.SubElement(element, "material", name=shape.name)
                ET.SubElement(material, "color", rgba=_fmt(shape.rgba))
    frictions = {s.friction for s in link.shapes if s.collides}
    if len(frictions) == 1:  # PyBullet's per-link contact friction (other readers ignore it)
        contact = ET.SubElement(node, "contact")
        ET.SubElement(contact, "lateral_friction", value=f"{frictions.pop():g}")


def _joint(robot: ET.Element, link: Link, frames: dict[str, np.ndarray]) -> None:
    j = link.joint
    kind = "fixed" if j is None else URDF_JOINT[j.type]
    node = ET.SubElement(robot, "joint", name=f"{link.name}_weld" if j is None else j.name)
    node.set("type", kind)
    _origin(node, np.linalg.inv(frames[link.parent]) @ frames[link.name])
    ET.SubElement(node, "parent", link=link.parent)
    ET.SubElement(node, "child", link=link.name)
    if j is None:
        return
    ET.SubElement(node, "axis", xyz=_fmt(j.axis))
    ET.SubElement(
        node,
        "limit",
        lower=f"{j.range[0]:.9g}",
        upper=f"{j.range[1]:.9g}",
        effort=f"{PASSIVE_EFFORT:g}",
        velocity=f"{PASSIVE_VELOCITY:g}",
    )
    ET.SubElement(node, "dynamics", damping=f"{j.damping:.9g}", friction=f"{j.frictionloss:.9g}")


def write_urdf(articulation: Articulation, folder: Path, name: str) -> Path:
    """Write `folder/name` with its meshes in `folder/meshes/`, referenced relatively."""
    files = link_mesh_files(articulation, folder)
    frames = {link.name: _frame(link) for link in articulation.links}
    robot = ET.Element("robot", name=articulation.name)
    for link in articulation.links:
        _link(robot, link, frames[link.name], files)
    for link in articulation.links[1:]:
        _joint(robot, link, frames)
    ET.indent(robot)
    path = folder / name
    path.write_text('<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n")
    return path
