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
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import manifold3d as mf
import numpy as np
import trimesh

from realikea.errors import RealIkeaError

GENERATOR_VERSION = "1"  # bump when any generator's output changes (part of the cache key)

BORE_DIAMETER = 0.0034  # m, M4 tap drill (3.3 mm) plus clearance
BORE_DEPTH_RANGE = (0.006, 0.010)  # m, full-diameter depth of the blind bores
MAX_EXTENTS = (0.34, 0.08, 0.045)  # m, (x, y, z): what fits on the smallest drawer front

# ---------------------------------------------------------------------------------------------
# resolution (millimetre units below this line)

_SEG = 128  # circular segments of revolved bodies
_SEG_SMALL = 64  # circular segments of rods, bosses and swept sections
_FILLET_SEG = 96  # at most this many segments per full circle of a fillet
_FILLET_CHORD = 0.25  # mm, target chord length of fillet arcs
_TARGET_FACES = 6000  # meshes below this are refined (flat facets split) up to about this count
_MIN_WALL = 1.2  # mm of material required around a bore
_BORE_R = BORE_DIAMETER * 1000 / 2
_BORE_MIN, _BORE_MAX = (v * 1000 for v in BORE_DEPTH_RANGE)
_DRILL_TIP = _BORE_R / math.tan(math.radians(59.0))  # 118 degree drill point


@dataclass(frozen=True)
class Family:
    name: str  # e.g. "round_bar"
    category: str  # "knob" | "two_point" | "finger_pull"
    dims: tuple[str, ...]  # required dimension keys (metres)
    build: Callable[[Mapping[str, float]], trimesh.Trimesh]
    doc: str  # one line: what the family is


# ---------------------------------------------------------------------------------------------
# small geometry helpers


def _fail(family: str, msg: str) -> RealIkeaError:
    return RealIkeaError(f"part family {family!r}: {msg}")


def _fillet(points: Sequence[Sequence[float]], radii: Sequence[float]) -> np.ndarray:
    """Round the corners of a closed 2-D polygon; radii[i] is the fillet radius at vertex i."""
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    out: list[np.ndarray] = []
    for i in range(n):
        p, r = pts[i], float(radii[i])
        if r <= 0:
            out.append(p)
            continue
        u, v = pts[i - 1] - p, pts[(i + 1) % n] - p
        lu, lv = float(np.hypot(*u)), float(np.hypot(*v))
        u, v = u / lu, v / lv
        ang = math.acos(float(np.clip(u @ v, -1.0, 1.0)))
        if ang < 1e-6 or ang > math.pi - 1e-6:
            out.append(p)
            continue
        half = ang / 2
        d = r / math.tan(half)
        d_max = 0.49 * min(lu, lv)
        if d > d_max:
            d, r = d_max, d_max * math.tan(half)
        bis = (u + v) / np.hypot(*(u + v))
        c = p + bis * (r / math.sin(half))
        t1, t2 = p + u * d, p + v * d
        a1 = math.atan2(t1[1] - c[1], t1[0] - c[0])
        a2 = math.atan2(t2[1] - c[1], t2[0] - c[0])
        da = (a2 - a1 + math.pi) % (2 * math.pi) - math.pi
        full = min(_FILLET_SEG, max(16, round(2 * math.pi * r / _FILLET_CHORD)))
        k = max(2, math.ceil(abs(da) / (2 * math.pi) * full))
        for j in range(k + 1):
            a = a1 + da * j / k
            out.append(c + r * np.array([math.cos(a), math.sin(a)]))
    return np.array(out)


def _polygon(points: np.ndarray) -> mf.CrossSection:
    """A CrossSection from one simple polygon, whatever its orientation."""
    pts = np.asarray(points, dtype=float)
    x, y = pts[:, 0], pts[:, 1]
    if np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) < 0:
        pts = pts[::-1]
    return mf.CrossSection([np.ascontiguousarray(pts)])


def _revolve(profile_rz: np.ndarray, segments: int = _SEG) -> mf.Manifold:
    """Solid of revolution about +z from a closed (r, z) profile that runs along the axis."""
    return _polygon(profile_rz).revolve(circular_segments=segments)


def _rounded_rect(w: float, h: float, r: float, segments: int = _SEG_SMALL) -> mf.CrossSection:
    """A w x h rectangle centred on the origin with corner radius r."""
    r = min(r, w / 2 - 1e-6, h / 2 - 1e-6)
    if r <= 1e-6:
        return mf.CrossSection.square((w, h), center=True)
    core = mf.CrossSection.square((w - 2 * r, h - 2 * r), center=True)
    return core.offset(r, mf.JoinType.Round, circular_segments=segments)


def _extrude(cs: mf.CrossSection, length: float, axis: str, divisions: int = 0) -> mf.Manifold:
    """Extrude a section symmetrically along a part axis (a proper rotation, no mirroring).

    The section's (u, v) coordinates are (y, z) for axis x, (z, x) for axis y, (x, y) for axis z.
    """
    m = cs.extrude(length, n_divisions=divisions).translate((0.0, 0.0, -length / 2))
    if axis == "z":
        return m
    if axis == "x":  # (u, v, w) -> (x=w, y=u, z=v)
        mat = [[0, 0, 1, 0], [1, 0, 0, 0], [0, 1, 0, 0]]
    else:  # axis y: (u, v, w) -> (x=v, y=w, z=u)
        mat = [[0, 1, 0, 0], [0, 0, 1, 0], [1, 0, 0, 0]]
    return m.transform(np.array(mat, dtype=float))


def _cylinder_z(r: float, z0: float, z1: float, x: float = 0.0, y: float = 0.0) -> mf.Manifold:
    return mf.Manifold.cylinder(z1 - z0, r, r, _SEG_SMALL).translate((x, y, z0))


def _sweep(
    section: mf.CrossSection, path_xz: np.ndarray, step: float = 3.0, turn_deg: float = 4.0
) -> mf.Manifold:
    """Sweep a section along a planar path in the xz-plane (section u = in-plane normal, v = y).

    The section is extruded straight and then bent onto the path, so the result is one connected
    tube; the path must bend less sharply than the section's half-width. Rings are spaced at most
    `step` mm apart on straight runs and `turn_deg` degrees apart in bends.
    """
    path = np.asarray(path_xz, dtype=float)
    seg = np.diff(path, axis=0)
    seg_len = np.hypot(seg[:, 0], seg[:, 1])
    s = np.concatenate([[0.0], np.cumsum(seg_len)])
    tang = np.gradient(path, s, axis=0)
    tang /= np.linalg.norm(tang, axis=1, keepdims=True)
    turn = np.arccos(np.clip(np.sum(tang[1:] * tang[:-1], axis=1), -1.0, 1.0))
    # q: the path re-parametrized in ring divisions, dense where the path bends
    q = np.concatenate(
        [[0.0], np.cumsum(np.maximum(seg_len / step, turn / math.radians(turn_deg)))]
    )
    n_div = max(1, math.ceil(q[-1]))
    q *= n_div / q[-1]
    straight = section.extrude(float(n_div), n_divisions=n_div - 1)

    def bend(v: np.ndarray) -> np.ndarray:
        w = np.interp(v[:, 2], q, s)
        px, pz = np.interp(w, s, path[:, 0]), np.interp(w, s, path[:, 1])
        tx, tz = np.interp(w, s, tang[:, 0]), np.interp(w, s, tang[:, 1])
        norm = np.hypot(tx, tz)
        nx, nz = tz / norm, -tx / norm  # in-plane normal; (n, y, t) is right-handed
        return np.column_stack([px + v[:, 0] * nx, v[:, 1], pz + v[:, 0] * nz])

    return straight.warp_batch(bend)


def _arc(cx: float, cz: float, r: float, a0: float, a1: float, n: int) -> np.ndarray:
    a = np.linspace(a0, a1, n)
    return np.column_stack([cx + r * np.cos(a), cz + r * np.sin(a)])


def _u_path(cc: float, hc: float, rb: float, z0: float = -1.0) -> np.ndarray:
    """Centreline of a bent U/D handle: legs at x = +-cc/2 from z0, top at z = hc, bends rb."""
    x0 = cc / 2
    n_arc = 64
    left = _arc(-x0 + rb, hc - rb, rb, math.pi, math.pi / 2, n_arc)
    right = _arc(x0 - rb, hc - rb, rb, math.pi / 2, 0.0, n_arc)
    return np.vstack([[[-x0, z0]], left, right, [[x0, z0]]])


def _bore_depth(available: float, family: str = "") -> float:
    """Bore depth that leaves a floor of material under `available` mm of solid."""
    if available < _BORE_MIN + _DRILL_TIP + _MIN_WALL:
        raise _fail(
            family,
            f"only {available:.1f} mm of material above the mounting face: too "
            "little for a 6 mm M4 screw bore",
        )
    return float(np.clip(available - _DRILL_TIP - _MIN_WALL, _BORE_MIN, _BORE_MAX))


def _bores(xs: Sequence[float], depth: float) -> mf.Manifold:
    """Blind drilled bores along +z at (x, 0), opening on z = 0 (extends 1 mm below the plane)."""
    prof = np.array(
        [[0.0, -1.0], [_BORE_R, -1.0], [_BORE_R, depth], [0.0, depth + _DRILL_TIP]], dtype=float
    )
    tool = _revolve(prof, _SEG_SMALL)
    return mf.Manifold.batch_boolean([tool.translate((x, 0.0, 0.0)) for x in xs], mf.OpType.Add)


def _boss(r: float, height: float, x: float, fillet: float = 1.0) -> mf.Manifold:
    """A round screw boss on the mounting plane with a rounded top edge."""
    prof = _fillet([[0, 0], [r, 0], [r, height], [0, height]], [0, 0, fillet, 0])
    return _revolve(prof, _SEG_SMALL).translate((x, 0.0, 0.0))


def _finish(family: str, solid: mf.Manifold, bores: mf.Manifold) -> trimesh.Trimesh:
    """Trim to z >= 0, drill the bores, densify, check, and convert to a metre trimesh."""
    solid = solid.trim_by_plane((0.0, 0.0, 1.0), 0.0) - bores
    if solid.is_empty() or solid.volume() <= 0:
        raise _fail(family, "the dimensions make no solid")
    pieces = len(solid.decompose())
    if pieces != 1:
        raise _fail(family, f"the dimensions make {pieces} disconnected pieces, not one part")
    if solid.num_tri() < _TARGET_FACES:
        edge = math.sqrt(solid.surface_area() / (0.43 * _TARGET_FACES))
        solid = solid.refine_to_length(edge)
    mesh = solid.to_mesh64()
    verts = np.asarray(mesh.vert_properties, dtype=float)[:, :3] * 1e-3
    faces = np.asarray(mesh.tri_verts, dtype=np.int64)
    out = trimesh.Trimesh(verts, faces, process=False)
    if not (out.is_watertight and out.is_volume):
        raise _fail(family, "generator produced a non-watertight mesh (please report)")
    return out


def _need(family: str, ok: bool, msg: str) -> None:
    if not ok:
        raise _fail(family, msg)


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
