"""metadata.json of an exported configuration: what it is, its joint and resistance in every mode,
its dimensions, bounds and masses, its fidelity certificate and the room a fingertip can use.

Lengths in metres, masses in kilograms, angles in radians; positions in the cabinet frame
(origin at the bottom centre of the carcass's front plane, +x out of the front, +y to the
viewer's right, +z up) with the front closed, unless a field says otherwise.
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import numpy as np
import trimesh

from realikea.assets.catalog import Configuration
from realikea.assets.catch_geometry import BarCatch, LipCatch, NoCatch, catch_features_at
from realikea.export.model import Articulation, quat_wxyz
from realikea.sim.resistance import Resistance, handle_resistance, lever_arm
from realikea.sim.robot import PAD_THICKNESS

PART_LINK = "part"  # the body the part is mounted as (workflow step 5)
UNITS = "m, kg, s, rad unless a field's own `units` says otherwise"
FRAME = (
    "cabinet frame: origin at the bottom centre of the carcass's front plane, +x out of the "
    "front, +y to the viewer's right, +z up; front closed"
)
FINGERTIP = PAD_THICKNESS  # m: the Franka Hand's pad, 9 mm thick across the jaw gap
RESISTANCE_UNITS = {
    "slide": {"damping": "N s/m", "frictionloss": "N"},
    "hinge": {"damping": "N m s/rad", "frictionloss": "N m"},
}


def _vector(values) -> list[float]:
    return [float(v) for v in values]


def joint_record(articulation: Articulation) -> dict:
    """The front's joint: type, anchor and axis in the cabinet frame, range."""
    joint = articulation.moving_link.joint
    anchor, axis = articulation.joint_anchor_axis()
    return {
        "name": joint.name,
        "type": joint.type,
        "anchor": _vector(anchor),
        "axis": _vector(axis),
        "range": list(joint.range),
        "range_unit": "m" if joint.type == "slide" else "rad",
    }


def resistance_record(articulation: Articulation, modes: list[Resistance], mode: str) -> dict:
    """Damping and friction of every mode for this configuration (a hinge's scaled to its
    handle's lever arm, `realikea/sim/resistance.py`), and the mode the exported model carries
    (`articulation` is already at it: `with_resistance`)."""
    joint = articulation.moving_link.joint
    lever = None
    if joint.type == "hinge":
        lever = lever_arm(*articulation.joint_anchor_axis(), articulation.handle)
    scaled = {}
    for m in modes:
        damping, frictionloss = handle_resistance(
            joint.type, lever or 0.0, m.damping, m.frictionloss
        )
        scaled[m.name] = {"damping": damping, "frictionloss": frictionloss}
    return {
        "exported": {"mode": mode, "damping": joint.damping, "frictionloss": joint.frictionloss},
        "modes": scaled,
        "at_handle": {
            m.name: {"damping": m.damping, "frictionloss": m.frictionloss} for m in modes
        },
        "lever_arm": lever,
        "units": RESISTANCE_UNITS[joint.type],
        "at_handle_units": RESISTANCE_UNITS["slide"],
    }


def key_dimensions(config: Configuration) -> dict:
    """The catalog rows' dimensions: the part's (m) and the base's."""
    base = {k: v for k, v in asdict(config.base).items() if k not in ("id", "kind", "joint")}
    return {"part": dict(config.part.dims), "base": base}


def _box(points: np.ndarray) -> dict:
    low, high = points.min(axis=0), points.max(axis=0)
    return {"min": _vector(low), "max": _vector(high), "size": _vector(high - low)}


def part_bounds(articulation: Articulation, visual: Path) -> dict:
    """Axis-aligned bounds of the part's visual mesh in its own frame (z out of the front from
    the mounting plane, x along the part) and in the cabinet frame."""
    points = np.asarray(trimesh.load(visual, force="mesh").vertices)
    pose = articulation.link(PART_LINK).pose
    return {
        "part_frame": _box(points),
        "cabinet_frame": _box(points @ pose[:3, :3].T + pose[:3, 3]),
    }


def mass_model(articulation: Articulation) -> dict:
    """Each link's mass, centre of mass and principal inertia as the MJCF's compiled model has
    them (link frame = the MuJoCo body's frame); the static carcass is massless."""
    links = {
        link.name: {
            "mass": link.inertial.mass,
            "center_of_mass": _vector(link.inertial.pose[:3, 3]),
            "principal_moments": _vector(link.inertial.moments),
            "principal_axes_wxyz": _vector(quat_wxyz(link.inertial.pose)),
            "pose_wxyz": _vector(quat_wxyz(link.pose)),
            "position": _vector(link.pose[:3, 3]),
        }
        for link in articulation.links
    }
    moving = sum(link.inertial.mass for link in articulation.links[1:])
    return {"links": links, "moving_mass": moving, "units": "kg, m, kg m^2"}


def fingertip_clearance(visual: Path, category: str) -> dict:
    """The room a fingertip has behind a two-point bar (between its back and the front) or in the
    channel behind a finger pull's lip (between the lip's inner face and the back wall), read off
    the visual mesh (`catch_geometry`); null for knobs and for parts with nothing to get behind."""
    empty = {"feature": None, "clearance": None, "fingertip": FINGERTIP, "fits_fingertip": None}
    if category == "knob":
        return {**empty, "reason": "a knob is caught behind its head, not in a gap"}
    found = catch_features_at(str(visual), category)
    if isinstance(found, NoCatch):
        return {**empty, "reason": found.reason}
    if isinstance(found, BarCatch):
        feature, clearance = "gap behind the bar", found.proj - found.depth
    else:
        assert isinstance(found, LipCatch)
        feature, clearance = "channel behind the lip", found.channel
    return {
        "feature": feature,
        "clearance": clearance,
        "fingertip": FINGERTIP,
        "fits_fingertip": clearance >= FINGERTIP,
        "catch_features": asdict(found),
    }


def configuration_metadata(
    config: Configuration,
    articulation: Articulation,
    visual: Path,
    modes: list[Resistance],
    mode: str,
    certificate: dict,
    export: dict,
) -> dict:
    """Everything metadata.json holds for one exported configuration."""
    part, base = config.part, config.base
    return {
        "config_id": config.id,
        "part_id": part.id,
        "base_id": base.id,
        "category": part.category,
        "family": part.family,
        "kind": base.kind,
        "part_friction": {"class": part.friction, "coefficient": part.friction_coefficient},
        "units": UNITS,
        "frame": FRAME,
        "joint": joint_record(articulation),
        "resistance": resistance_record(articulation, modes, mode),
        "dimensions": key_dimensions(config),
        "part_bounds": part_bounds(articulation, visual),
        "mass_model": mass_model(articulation),
        "fidelity_certificate": certificate,
        "fingertip_clearance": fingertip_clearance(visual, part.category),
        "export": export,
    }
