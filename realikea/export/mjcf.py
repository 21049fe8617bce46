"""MJCF: the built model file of one collision source with its joint at the exported resistance,
and exactly the meshes it uses."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from realikea.export.model import Articulation, link_mesh_files

RESISTANCE_SCHEMA = (
    "MJCF <joint damping frictionloss/> (slide: N s/m and N; hinge: N m s/rad and N m), "
    "friction loss with solreffriction/solimpfriction"
)


def write_mjcf(articulation: Articulation, folder: Path, name: str) -> Path:
    """The built MJCF written to `folder/name` with the articulation's joint damping and friction
    loss, its meshes at the same relative paths."""
    link_mesh_files(articulation, folder)
    tree = ET.parse(articulation.mjcf)
    joint = articulation.moving_link.joint
    node = next(j for j in tree.iter("joint") if j.get("name") == joint.name)
    node.set("damping", f"{joint.damping:.9g}")
    node.set("frictionloss", f"{joint.frictionloss:.9g}")
    tree.write(folder / name, encoding="unicode")
    return folder / name
