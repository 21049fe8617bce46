"""Knob families: solids of revolution (and one hull) around the single central bore."""

from __future__ import annotations

import math
from collections.abc import Mapping

import manifold3d as mf
import numpy as np
import trimesh

from realikea.assets.shapes.solids import (
    _BORE_R,
    _MIN_WALL,
    _arc,
    _bore_depth,
    _bores,
    _fillet,
    _finish,
    _need,
    _revolve,
)

# ---------------------------------------------------------------------------------------------
# knobs: solids of revolution (and one hull) around the single central bore


def _knob_base(d: Mapping[str, float], family: str) -> tuple[float, float, float, float]:
    """Shared neck/flange numbers: (neck radius, base radius, flange height, head underside z)."""
    rn, rb = d["neck_diameter"] / 2, d["base_diameter"] / 2
    zu = d["projection"] - d["head_thickness"]
    _need(family, d["head_thickness"] < d["projection"] - 2.0, "head_thickness must leave a neck")
    _need(family, rn >= _BORE_R + _MIN_WALL + 0.5, "neck_diameter too small to hold an M4 bore")
    _need(family, rn < d["diameter"] / 2 - 1.0, "neck_diameter must be smaller than diameter")
    _need(family, rb >= rn, "base_diameter must be at least neck_diameter")
    fh = 1.5 if rb > rn + 0.5 else 0.0
    _need(family, zu > fh + 1.0, "head_thickness leaves no room for the base flange")
    return rn, rb, fh, zu


def _knob_profile(
    d: Mapping[str, float], family: str, side_frac: float, neck_fillet: float
) -> np.ndarray:
    """Profile of a head (vertical rim, then an elliptic dome) on a neck with a base flange."""
    rn, rb, fh, zu = _knob_base(d, family)
    rh, top, ht = d["diameter"] / 2, d["projection"], d["head_thickness"]
    zs = zu + ht * side_frac  # top of the vertical rim, start of the dome
    rim = min(1.5, ht * side_frac * 0.45)
    pts = [[0, 0], [rb, 0]]
    rad = [0, 0]
    if fh > 0:
        pts += [[rb, fh], [rn, fh]]
        rad += [0.6, min(1.0, (rb - rn) * 0.45)]
    pts += [[rn, zu], [rh, zu]]
    rad += [neck_fillet, rim]
    coarse = _fillet(pts + [[rh, zs], [0, zs]], rad + [0, 0])[:-2]
    dome = _arc(0.0, 0.0, 1.0, 0.0, math.pi / 2, 48)
    dome = np.column_stack([rh * dome[:, 0], zs + (top - zs) * dome[:, 1]])
    dome[-1, 0] = 0.0
    return np.vstack([coarse, dome])


def _knob_finish(family: str, solid: mf.Manifold, projection: float) -> trimesh.Trimesh:
    return _finish(family, solid, _bores([0.0], _bore_depth(projection, family)))


def _build_round(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "round"
    _need(fam, d["diameter"] >= 10.0, "diameter must be at least 10 mm")
    prof = _knob_profile(d, fam, side_frac=0.45, neck_fillet=1.2)
    return _knob_finish(fam, _revolve(prof), d["projection"])


def _build_mushroom(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "mushroom"
    _need(fam, d["neck_diameter"] <= 0.7 * d["diameter"], "a mushroom neck must be narrow")
    prof = _knob_profile(d, fam, side_frac=0.18, neck_fillet=2.0)
    return _knob_finish(fam, _revolve(prof), d["projection"])


def _build_cylindrical(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "cylindrical"
    r, top, gd, pitch = d["diameter"] / 2, d["projection"], d["groove_depth"], d["groove_pitch"]
    _need(fam, r - gd >= _BORE_R + _MIN_WALL + 1.0, "groove_depth too deep for the diameter")
    edge = min(2.0, 0.2 * r)
    lo, hi = 0.2 * top, top - max(2.5, 1.5 * edge)
    n = int((hi - lo) // pitch)
    _need(fam, n >= 2, "groove_pitch too large: fewer than two grooves fit on the knob")
    gw = 0.45 * pitch
    z0 = (lo + hi) / 2 - (n - 1) * pitch / 2
    pts, rad = [[0, 0], [r, 0]], [0, 0.4]
    for k in range(n):
        zc = z0 + k * pitch
        pts += [[r, zc - gw / 2], [r - gd, zc - gw / 2], [r - gd, zc + gw / 2], [r, zc + gw / 2]]
        rad += [0.25, 0.15, 0.15, 0.25]
    pts += [[r, top], [0, top]]
    rad += [edge, 0]
    return _knob_finish(fam, _revolve(_fillet(pts, rad)), top)


def _build_square(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "square"
    w, top, ht, e = d["width"], d["projection"], d["head_thickness"], d["edge_radius"]
    _need(fam, e < min(w, ht) / 2, "edge_radius must be under half the width and head_thickness")
    dd = dict(d, diameter=w, base_diameter=d["neck_diameter"] + 3.0)
    rn, rb, fh, zu = _knob_base(dd, fam)
    h = w / 2 - e
    spheres = [
        mf.Manifold.sphere(e, 48).translate((sx * h * f, sy * h * f, z))
        for sx in (-1, 1)
        for sy in (-1, 1)
        for z, f in ((zu + e, 1.0), (top - e, 0.94))  # slightly tapered towards the face
    ]
    head = mf.Manifold.batch_hull(spheres)
    neck = _fillet(
        [[0, 0], [rb, 0], [rb, fh], [rn, fh], [rn, zu + e], [0, zu + e]],
        [0, 0, 0.6, min(1.0, (rb - rn) * 0.45), 0, 0],
    )
    return _knob_finish(fam, head + _revolve(neck), top)


def _build_tapered(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "tapered"
    rt, rb, top, e = d["diameter"] / 2, d["base_diameter"] / 2, d["projection"], d["edge_radius"]
    _need(fam, min(rt, rb) >= _BORE_R + _MIN_WALL + 1.0, "diameters too small for an M4 bore")
    _need(fam, e < min(rt, top) / 2, "edge_radius too large")
    # a flared (trumpet) side when the face is wider than the base, a straight cone otherwise
    dome = min(1.5, 0.08 * rt)
    z_rim = top - dome - 2.2 * e  # short straight rim so the face keeps its full diameter
    _need(fam, z_rim > 0.55 * top + 1.0, "edge_radius too large for the projection")
    if rt > rb:  # flare: stay slim, then sweep out to the face on a large radius
        mid_r, bend, rim_bend = rb + 0.15 * (rt - rb), 0.6 * top, 0.18 * top
    else:  # cone: one straight taper into a short cylindrical cap
        mid_r, bend, rim_bend = rb + (rt - rb) * 0.55 * top / z_rim, 0.0, 1.5
    pts = [[0, 0], [rb, 0], [mid_r, 0.55 * top], [rt, z_rim], [rt, top - dome], [0.5 * rt, top]]
    prof = _fillet(pts + [[0, top]], [0, 0, bend, rim_bend, e, 2.0 * rt, 0])
    return _knob_finish(fam, _revolve(prof), top)
