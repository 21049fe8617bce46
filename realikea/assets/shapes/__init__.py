"""Procedural solid models of every part family (knobs, two-point handles, finger pulls).

Each generator builds one part with manifold3d (revolves, extrusions, sweeps and booleans) and
returns a watertight ``trimesh.Trimesh`` in the *part frame*:

* metres; origin = the mounting point on the mounting plane z = 0 (the furniture front's outer
  surface); +z points outward, away from the furniture;
* +x along the part's long axis (the bar of a two-point handle, the profile of an edge pull);
* +y is "up" when the part is mounted horizontally on a drawer; finger-pull lips open towards -y;
* the solid lies at z >= 0, centred on x = 0 and on the mounting point (the screw bores sit at
  y = 0, at x = 0 for one bore and at x = +-cc/2 for two).

Every part carries one or two blind M4 screw bores (``BORE_DIAMETER``, 6-10 mm deep with a drill
point) that open only on the mounting face z = 0; they are the internal features the cleaning
stage of the workflow removes.

Internally the generators work in millimetres (the unit hardware is drawn in) and scale the
finished mesh to metres.

One module per category (`knobs`, `two_point`, `finger_pulls`) over the toolkit in `solids`;
this module is the registry, `FAMILIES`, and `part_mesh`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import trimesh

from realikea.assets.shapes.finger_pulls import _build_cup, _build_edge, _build_lip
from realikea.assets.shapes.knobs import (
    _build_cylindrical,
    _build_mushroom,
    _build_round,
    _build_square,
    _build_tapered,
)
from realikea.assets.shapes.solids import GENERATOR_VERSION, Family, _fail
from realikea.assets.shapes.two_point import (
    _build_bow,
    _build_d_handle,
    _build_flat_bar,
    _build_round_bar,
    _build_u_handle,
)
from realikea.errors import RealIkeaError

__all__ = ["FAMILIES", "GENERATOR_VERSION", "Family", "part_mesh"]


# ---------------------------------------------------------------------------------------------
# registry


def _family(name, category, dims, build, doc) -> tuple[str, Family]:
    return name, Family(name, category, tuple(dims), build, doc)


_KNOB = ("diameter", "projection", "head_thickness", "neck_diameter", "base_diameter")

FAMILIES: dict[str, Family] = dict(
    [
        _family("round", "knob", _KNOB, _build_round, "disc knob with a rounded rim on a neck"),
        _family(
            "mushroom", "knob", _KNOB, _build_mushroom, "dome head on a narrow neck (undercut)"
        ),
        _family(
            "cylindrical",
            "knob",
            ("diameter", "projection", "groove_depth", "groove_pitch"),
            _build_cylindrical,
            "straight cylinder knob with circumferential grip grooves",
        ),
        _family(
            "square",
            "knob",
            ("width", "projection", "head_thickness", "edge_radius", "neck_diameter"),
            _build_square,
            "square head with rounded edges on a round neck",
        ),
        _family(
            "tapered",
            "knob",
            ("diameter", "base_diameter", "projection", "edge_radius"),
            _build_tapered,
            "flared (trumpet) or conical knob without a separate neck",
        ),
        _family(
            "round_bar",
            "two_point",
            ("cc", "length", "bar_diameter", "post_diameter", "projection"),
            _build_round_bar,
            "round bar on two round posts",
        ),
        _family(
            "flat_bar",
            "two_point",
            ("cc", "length", "bar_width", "bar_thickness", "post_diameter", "projection"),
            _build_flat_bar,
            "flat rectangular bar with rounded edges on two round posts",
        ),
        _family(
            "d_handle",
            "two_point",
            ("cc", "rod_diameter", "projection", "bend_radius"),
            _build_d_handle,
            "one round rod bent into a D (square-cornered U)",
        ),
        _family(
            "u_handle",
            "two_point",
            ("cc", "strap_width", "strap_thickness", "projection", "bend_radius"),
            _build_u_handle,
            "flat strap bent into a U, on round feet",
        ),
        _family(
            "bow",
            "two_point",
            ("cc", "bar_width", "bar_thickness", "projection", "foot_diameter"),
            _build_bow,
            "arched (circular-arc) bar on two round feet",
        ),
        _family(
            "edge",
            "finger_pull",
            ("cc", "length", "height", "projection", "lip_drop", "thickness"),
            _build_edge,
            "long profile along x with a down-turned lip over a finger channel",
        ),
        _family(
            "lip",
            "finger_pull",
            ("length", "height", "projection", "lip_drop", "thickness"),
            _build_lip,
            "short tapered tab with a down-turned lip on a rounded back plate",
        ),
        _family(
            "cup",
            "finger_pull",
            ("cc", "length", "height", "projection", "thickness"),
            _build_cup,
            "half-shell bin pull, hollow open at the bottom, on screw ears",
        ),
    ]
)


def part_mesh(family: str, dims: Mapping[str, float]) -> trimesh.Trimesh:
    """Build the watertight visual mesh of one part in its part frame."""
    fam = FAMILIES.get(family)
    if fam is None:
        raise RealIkeaError(
            f"unknown part family {family!r}; known families: {', '.join(sorted(FAMILIES))}"
        )
    mm: dict[str, float] = {}
    for key in fam.dims:
        value = dims.get(key)
        if value is None or value == "":
            raise _fail(family, f"missing dimension {key!r} (needs {', '.join(fam.dims)})")
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise _fail(family, f"dimension {key!r} = {value!r} is not a number") from None
        if not math.isfinite(v) or v <= 0:
            raise _fail(family, f"dimension {key!r} must be a positive length in metres, got {v}")
        if v > 1.0:
            raise _fail(family, f"dimension {key!r} = {v} m is implausible; dimensions are metres")
        mm[key] = v * 1000.0
    return fam.build(mm)
