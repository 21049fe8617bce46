"""Step 6, simulation integration: one self-contained MJCF per configuration and source."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco

from realikea.assets.workflow.assembly import (
    FRICTION_SOLIMP,
    FRICTION_SOLREF,
    VISUAL_GROUP,
    Assembly,
    Body,
    Geom,
)
from realikea.errors import RealIkeaError
from realikea.files import atomic_write_text


def _fmt(values) -> str:
    return " ".join(f"{float(v):.6g}" for v in values)


def mjcf_text(assembly: Assembly, root_name: str = "unit") -> str:
    """The MJCF document: meshes relative to the file, all bodies under one movable root."""
    model = ET.Element("mujoco", model=assembly.name)
    ET.SubElement(model, "compiler", angle="radian", autolimits="true")
    ET.SubElement(model, "option", timestep="0.002", cone="elliptic", impratio="10")
    asset = ET.SubElement(model, "asset")
    for name, file in assembly.meshes.items():
        ET.SubElement(asset, "mesh", name=name, file=file)
    world = ET.SubElement(model, "worldbody")
    ET.SubElement(world, "light", name="key", pos="1.5 -1 2.5", dir="-0.5 0.3 -1")
    root = ET.SubElement(world, "body", name=root_name)
    for body in assembly.bodies:
        _body(root, body)
    ET.indent(model)
    return ET.tostring(model, encoding="unicode") + "\n"


def _body(parent: ET.Element, body: Body) -> None:
    node = ET.SubElement(parent, "body", name=body.name, pos=_fmt(body.pos), quat=_fmt(body.quat))
    if body.joint is not None:
        j = body.joint
        ET.SubElement(
            node,
            "joint",
            name=j.name,
            type=j.type,
            pos=_fmt(j.pos),
            axis=_fmt(j.axis),
            range=_fmt(j.range),
            damping=f"{j.damping:g}",
            frictionloss=f"{j.frictionloss:g}",
            solreffriction=_fmt(FRICTION_SOLREF),
            solimpfriction=_fmt(FRICTION_SOLIMP),
        )
    for geom in body.geoms:
        _geom(node, geom)
    for site in body.sites:
        ET.SubElement(node, "site", name=site.name, pos=_fmt(site.pos), quat=_fmt(site.quat))
    for child in body.children:
        _body(node, child)


def _geom(parent: ET.Element, g: Geom) -> None:
    attrs = {"name": g.name, "pos": _fmt(g.pos), "quat": _fmt(g.quat), "rgba": _fmt(g.rgba)}
    if g.box is not None:
        attrs.update(type="box", size=_fmt(g.box))
    else:
        attrs.update(type="mesh", mesh=g.mesh)
    if g.collides:
        attrs.update(group=str(g.group), friction=f"{g.friction:g} 0.005 0.0001")
    else:
        attrs.update(group=str(VISUAL_GROUP), contype="0", conaffinity="0")
    attrs["density"] = f"{g.density:g}"
    ET.SubElement(parent, "geom", attrs)


def write_mjcf(assembly: Assembly, path: Path) -> mujoco.MjModel:
    """Write the MJCF atomically after checking that MuJoCo compiles it from that folder."""
    text = mjcf_text(assembly)
    probe = path.with_name(f".{path.name}.check.xml")
    try:
        probe.write_text(text)
        model = mujoco.MjModel.from_xml_path(str(probe))
    except ValueError as err:
        raise RealIkeaError(f"{assembly.name}: MuJoCo rejects the assembled model: {err}") from err
    finally:
        probe.unlink(missing_ok=True)
    atomic_write_text(path, text)
    return model
