"""Two-point handle families: a bar or bent rod on two posts at x = +-cc/2."""

from __future__ import annotations

import math
from collections.abc import Mapping

import manifold3d as mf
import numpy as np
import trimesh

from realikea.assets.shapes.solids import (
    _BORE_R,
    _DRILL_TIP,
    _MIN_WALL,
    _SEG_SMALL,
    _bore_depth,
    _bores,
    _boss,
    _extrude,
    _fillet,
    _finish,
    _need,
    _revolve,
    _rounded_rect,
    _sweep,
    _u_path,
)

# ---------------------------------------------------------------------------------------------
# two-point handles: a bar or bent rod on two posts at x = +-cc/2


def _post(r: float, top: float, x: float) -> mf.Manifold:
    """A round post from the mounting plane to z = top, with a small foot flange."""
    rf = r + 1.5
    prof = _fillet(
        [[0, 0], [rf, 0], [rf, 1.5], [r, 1.5], [r, top], [0, top]], [0, 0, 0.6, 0.7, 0, 0]
    )
    return _revolve(prof).translate((x, 0.0, 0.0))


def _check_posts(fam: str, cc: float, length: float, post_d: float) -> None:
    _need(fam, post_d / 2 >= _BORE_R + _MIN_WALL + 0.5, "post_diameter too small for an M4 bore")
    _need(fam, cc > 2 * post_d, "cc too small for the posts")
    _need(fam, length >= cc + post_d, "length must be at least cc + post_diameter")


def _build_round_bar(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "round_bar"
    cc, length, bd, pd, proj = (
        d[k] for k in ("cc", "length", "bar_diameter", "post_diameter", "projection")
    )
    _check_posts(fam, cc, length, pd)
    _need(fam, proj > bd + 3.0, "bar_diameter must be well under projection (no gap behind bar)")
    r, zb = bd / 2, proj - bd / 2
    end = min(0.45 * r, 2.0)
    bar = _revolve(
        _fillet(
            [[0, -length / 2], [r, -length / 2], [r, length / 2], [0, length / 2]],
            [0, end, end, 0],
        ),
        96,
    )
    bar = bar.rotate((0.0, 90.0, 0.0)).translate((0.0, 0.0, zb))
    posts = [_post(pd / 2, zb, x) for x in (-cc / 2, cc / 2)]
    solid = mf.Manifold.batch_boolean([bar, *posts], mf.OpType.Add)
    return _finish(fam, solid, _bores([-cc / 2, cc / 2], _bore_depth(zb, fam)))


def _build_flat_bar(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "flat_bar"
    cc, length, w, t, pd, proj = (
        d[k] for k in ("cc", "length", "bar_width", "bar_thickness", "post_diameter", "projection")
    )
    _check_posts(fam, cc, length, pd)
    _need(fam, proj > t + 3.0, "bar_thickness must be well under projection (no gap behind bar)")
    _need(fam, w >= pd, "bar_width must be at least post_diameter")
    zb = proj - t / 2
    section = _rounded_rect(w, t, 0.35 * min(w, t))
    bar = _extrude(section, length, "x", divisions=math.ceil(length / 2.0))
    plan = _extrude(_rounded_rect(length, w, 0.3 * w), t + 2.0, "z")  # rounded ends in plan
    bar = (bar ^ plan).translate((0.0, 0.0, zb))
    posts = [_post(pd / 2, zb, x) for x in (-cc / 2, cc / 2)]
    solid = mf.Manifold.batch_boolean([bar, *posts], mf.OpType.Add)
    return _finish(fam, solid, _bores([-cc / 2, cc / 2], _bore_depth(zb, fam)))


def _check_bent(fam: str, cc: float, proj: float, t: float, rb: float) -> float:
    """Checks shared by bent handles; returns the centreline height of the top run."""
    hc = proj - t / 2
    _need(fam, proj > t + 3.0, "the rod/strap must be well under projection (no gap behind it)")
    _need(fam, rb > t / 2 + 0.5, "bend_radius must exceed half the rod/strap thickness")
    _need(fam, hc >= rb, "projection too small for the bend_radius")
    _need(fam, cc / 2 >= rb + t, "cc too small for the bend_radius")
    return hc


def _build_d_handle(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "d_handle"
    cc, rd, proj, rb = d["cc"], d["rod_diameter"], d["projection"], d["bend_radius"]
    _need(fam, rd / 2 >= _BORE_R + _MIN_WALL + 0.5, "rod_diameter too small for an M4 bore")
    hc = _check_bent(fam, cc, proj, rd, rb)
    rod = _sweep(mf.CrossSection.circle(rd / 2, _SEG_SMALL), _u_path(cc, hc, rb))
    rf = rd / 2 + 1.5  # ferrule under each leg
    ferrules = [_boss(rf, 2.5, x, fillet=0.8) for x in (-cc / 2, cc / 2)]
    solid = mf.Manifold.batch_boolean([rod, *ferrules], mf.OpType.Add)
    return _finish(fam, solid, _bores([-cc / 2, cc / 2], _bore_depth(hc, fam)))


def _build_u_handle(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "u_handle"
    cc, w, t, proj, rb = (
        d[k] for k in ("cc", "strap_width", "strap_thickness", "projection", "bend_radius")
    )
    _need(fam, w >= 2 * _BORE_R + 2 * _MIN_WALL + 2.0, "strap_width too small for the feet")
    hc = _check_bent(fam, cc, proj, t, rb)
    section = _rounded_rect(t, w, 0.3 * t)
    strap = _sweep(section, _u_path(cc, hc, rb))
    depth = _bore_depth(7.0 + _DRILL_TIP + _MIN_WALL, fam)  # 7 mm: the feet stay short
    rf = max(t / 2, _BORE_R + _MIN_WALL + 0.8)  # round foot under each leg holds the bore
    feet = [_boss(rf, depth + _DRILL_TIP + 2.5, x) for x in (-cc / 2, cc / 2)]
    solid = mf.Manifold.batch_boolean([strap, *feet], mf.OpType.Add)
    return _finish(fam, solid, _bores([-cc / 2, cc / 2], depth))


def _build_bow(d: Mapping[str, float]) -> trimesh.Trimesh:
    fam = "bow"
    cc, w, t, proj, fd = (
        d[k] for k in ("cc", "bar_width", "bar_thickness", "projection", "foot_diameter")
    )
    _need(fam, proj > t + 3.0, "bar_thickness must be well under projection (no gap behind bar)")
    _need(fam, fd / 2 >= _BORE_R + _MIN_WALL + 0.5, "foot_diameter too small for an M4 bore")
    _need(fam, cc > 2 * fd, "cc too small for the feet")
    hc = proj - t / 2  # apex of the centreline; the arch meets the plane at x = +-cc/2
    radius = ((cc / 2) ** 2 + hc**2) / (2 * hc)
    _need(fam, radius > t, "the arch is bent too sharply for its thickness")
    cz = hc - radius
    a_end = math.acos(max(-1.0, (-t - cz) / radius))  # run the arc on below the plane
    ang = np.linspace(math.pi / 2 + a_end, math.pi / 2 - a_end, 241)
    path = np.column_stack([radius * np.cos(ang), cz + radius * np.sin(ang)])
    bar = _sweep(_rounded_rect(t, w, 0.45 * min(t, w)), path)
    depth = _bore_depth(min(hc, 12.0), fam)
    feet = [_boss(fd / 2, depth + _DRILL_TIP + 2.5, x, fillet=1.5) for x in (-cc / 2, cc / 2)]
    solid = mf.Manifold.batch_boolean([bar, *feet], mf.OpType.Add)
    return _finish(fam, solid, _bores([-cc / 2, cc / 2], depth))
