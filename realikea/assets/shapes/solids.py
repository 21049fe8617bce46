"""The solid-modelling toolkit of the part generators (millimetres, manifold3d): fillets,
revolves, extrusions, sweeps, screw bores and the finishing into a watertight part-frame mesh."""

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
