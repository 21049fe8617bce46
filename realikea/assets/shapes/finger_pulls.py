"""Finger-pull families: a roof with a down-turned lip, leaving a channel open towards -y."""

from __future__ import annotations

import math
from collections.abc import Mapping

import manifold3d as mf
import numpy as np
import trimesh

from realikea.assets.shapes.solids import (
    _BORE_MIN,
    _BORE_R,
    _DRILL_TIP,
    _MIN_WALL,
    _bore_depth,
    _bores,
    _boss,
    _extrude,
    _fillet,
    _finish,
    _need,
    _polygon,
    _rounded_rect,
)

# ---------------------------------------------------------------------------------------------
# finger pulls: a roof with a down-turned lip, leaving a channel open towards -y


def _roof_thickness(t: float) -> float:
    return max(2 * _BORE_R + 2 * _MIN_WALL + 0.6, t)


def _lip_profile(d: Mapping[str, float], family: str) -> tuple[mf.CrossSection, float]:
    """(y, z) profile: back plate, roof holding the bores at y = 0, down-turned lip at the front."""
    h, p, drop, t = d["height"], d["projection"], d["lip_drop"], d["thickness"]
    rt = _roof_thickness(t)
    _need(family, p - 2 * t >= 3.0, "projection too small: no channel between plate and lip")
    _need(family, p >= _BORE_MIN + _DRILL_TIP + _MIN_WALL, "projection too small for an M4 bore")
    _need(family, h >= rt + t, f"height must be at least {rt + t:.1f} mm")
    _need(family, t >= 1.0, "thickness must be at least 1 mm")
    y_top = rt / 2
    y0, y_roof, y_lip = y_top - h, y_top - rt, y_top - rt - drop
    pts = [
        [y0, 0.0],
        [y_top, 0.0],
        [y_top, p],
        [y_lip, p],
        [y_lip, p - t],
        [y_roof, p - t],
        [y_roof, t],
        [y0, t],
    ]
    rad = [0, 0, min(2.0, 0.6 * t), 0.45 * t, 0.45 * t, 0.8, 0.8, 0.45 * t]
    return _polygon(_fillet(pts, rad)), _bore_depth(p, family)


def _build_edge(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "edge"
    cc, length, p = d["cc"], d["length"], d["projection"]
    _need(fam, length >= cc + 2 * _BORE_R + 8.0, "length must exceed cc by at least 11.4 mm")
    section, depth = _lip_profile(d, fam)
    body = _extrude(section, length, "x", divisions=math.ceil(length / 2.0))
    ext = max(d["height"], _roof_thickness(d["thickness"]) + d["lip_drop"]) + 2.0
    plan = _extrude(_polygon(_plan_ends(length, p, min(4.0, 0.4 * p))), ext * 2, "y")
    return _finish(fam, body ^ plan, _bores([-cc / 2, cc / 2], depth))


def _plan_ends(length: float, p: float, r: float) -> np.ndarray:
    """(z, x) outline of a profile seen from above: square at the plate, rounded at the front."""
    pts = [[-1.0, -length / 2], [-1.0, length / 2], [p, length / 2], [p, -length / 2]]
    return _fillet(pts, [0, 0, r, r])


def _build_lip(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "lip"
    length, h, p, drop, t = (
        d[k] for k in ("length", "height", "projection", "lip_drop", "thickness")
    )
    _need(fam, length >= 16.0, "length must be at least 16 mm")
    _need(fam, h >= _roof_thickness(t) + t, "height too small for the roof and plate")
    section, depth = _lip_profile(dict(d, height=_roof_thickness(t) + t), fam)
    tab = _extrude(section, length, "x", divisions=math.ceil(length / 1.0))
    # seen from above the tab narrows towards its rounded front edge
    taper = [[-1.0, -length / 2], [-1.0, length / 2], [p, 0.4 * length], [p, -0.4 * length]]
    r_plan = min(0.3 * length, 0.45 * p)
    plan = _polygon(_fillet(taper, [0, 0, r_plan, r_plan]))
    tab = tab ^ _extrude(plan, 2 * (_roof_thickness(t) + drop) + 4.0, "y")
    rt = _roof_thickness(t)
    plate = _extrude(_rounded_rect(length, h, min(length, h) * 0.3), t, "z")
    plate = plate.translate((0.0, rt / 2 - h / 2, t / 2))
    return _finish(fam, tab + plate, _bores([0.0], depth))


def _build_cup(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "cup"
    cc, length, h, p, t = (d[k] for k in ("cc", "length", "height", "projection", "thickness"))
    a, b = length / 2, h
    _need(fam, t >= 1.0 and p - t >= 8.0, "projection too small for a hollow behind the shell")
    _need(fam, h - t >= 8.0 and a - t >= 10.0, "shell too small for fingertips")
    y_open = -h / 2  # the shell spans y in [-h/2, h/2]; the ears sit at y = 0
    ai, bi, ci = a - t, b - t, p - t
    x_hollow = ai * math.sqrt(max(0.0, 1 - (h / 2) ** 2 / bi**2))  # hollow half-width at y = 0
    rb = _BORE_R + _MIN_WALL + 1.3  # boss radius
    _need(fam, cc / 2 - rb >= x_hollow, "cc too small: the screw bosses fall into the hollow")
    outer = mf.Manifold.sphere(1.0, 128).scale((a, b, p)).translate((0.0, y_open, 0.0))
    outer = outer.trim_by_plane((0.0, 1.0, 0.0), y_open)
    inner = mf.Manifold.sphere(1.0, 128).scale((ai, bi, ci)).translate((0.0, y_open, 0.0))
    shell = outer - inner
    ft, rim = 2.0, 1.5
    ear = _rounded_rect(cc + 2 * rb + 2.0, 2 * rb + 2.0, rb + 1.0)
    hood = mf.CrossSection.circle(1.0, 128).scale((a + rim, b + rim)).translate((0.0, y_open))
    hood = hood ^ mf.CrossSection.square((2 * (a + rim) + 2, b + rim + 1)).translate(
        (-(a + rim) - 1, y_open)
    )
    flange = _extrude(ear + hood, ft, "z").translate((0.0, 0.0, ft / 2)) - inner
    depth = _bore_depth(7.0 + _DRILL_TIP + _MIN_WALL, fam)  # 7 mm: the ears stay low
    bosses = [_boss(rb, depth + _DRILL_TIP + 2.0, x) for x in (-cc / 2, cc / 2)]
    solid = mf.Manifold.batch_boolean([shell, flange, *bosses], mf.OpType.Add)
    return _finish(fam, solid, _bores([-cc / 2, cc / 2], depth))
