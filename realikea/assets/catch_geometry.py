"""What a fingertip can catch on a part, measured on its visual mesh in the part frame.

Works on any part, catalog or imported, from the mesh alone (metres, part frame: z out of the
front from the mounting plane z = 0, x along the part's long axis, y "up" for a drawer's part,
finger-pull lips opening towards -y). Everything is read off the cross-section in the plane
x = 0, where the hand catches the part:

* two-point handles: the bar's section polygon (its top, its height along y, its depth along z);
  the gap behind it is what a loop of fingertips closes in.
* knobs: the profile r(z), the extent of the material along +y (the side a wedge comes from);
  the head is the band of z at full radius nearest the face, its back rim the band's lowest z,
  the neck the narrowest profile below it.
* finger pulls: per z, the first material met coming from -y (where fingers come from); the lip
  is the front run of low first material, the channel behind it the run of higher first
  material, bounded by the back plate (or the front itself).

A part with nothing to get behind gives `NoCatch` with a reason instead of features.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import trimesh

from realikea.errors import RealIkeaError

STEP = 1e-4  # m: spacing of the scan lines across the section
SECTION_X = 1e-6  # m: the section plane, just off x = 0 so it does not run through vertices
FULL_RADIUS_TOL = 5e-4  # m: a knob's profile within this of its largest radius is "full"
# m: the least room a fingertip pad needs behind a feature (undercut under a knob's head, a
# lip's drop below its channel's roof, the channel's width, the gap behind a bar). The pad sinks
# about 0.9 mm into what it presses (docs/task.md), so under 2 mm it keeps less than
# 1 mm bearing behind the edge and rolls off it. The catalog's parts with a real head offer
# 2.5 mm or more, the grooves of cylindrical knobs 0.6-1.5 mm.
MIN_ROOM = 2e-3
LIP_RISE = 5e-4  # m: first material this far above a lip's bottom is the channel behind it


@dataclass(frozen=True)
class BarCatch:
    """A two-point handle's bar at x = 0: the pads close in the gap `proj - depth` behind it."""

    proj: float  # z of the bar's top
    height: float  # the bar's extent along y
    depth: float  # the bar's extent along z


@dataclass(frozen=True)
class KnobCatch:
    """A knob's head at x = 0 on the +y side: a pad wedges behind its back rim."""

    radius: float  # the head's radius (its extent along +y)
    back: float  # z of the head's back rim: the lowest z still at full radius
    neck: float  # the narrowest radius between the foot and the back rim


@dataclass(frozen=True)
class LipCatch:
    """A finger pull's lip at x = 0: fingers from -y get behind its inner bottom edge."""

    edge_y: float  # y of the lip's inner bottom edge (the lip's lowest point)
    edge_z: float  # z of the lip's inner face, where the channel ends
    back: float  # z of the channel's back wall (the back plate's outer face, or the front)
    top: float  # y of the channel's roof underside (its highest point)

    @property
    def channel(self) -> float:
        """The room behind the lip along the pull (m): what a fingertip pad must enter."""
        return self.edge_z - self.back


@dataclass(frozen=True)
class NoCatch:
    """Nothing a fingertip can get behind; `reason` says why, for people."""

    reason: str


CatchFeatures = BarCatch | KnobCatch | LipCatch


def catch_features(mesh: trimesh.Trimesh, category: str) -> CatchFeatures | NoCatch:
    """The catchable geometry of a part (knob, two_point or finger_pull) from its mesh."""
    segments = _section_yz(mesh)
    if len(segments) == 0:
        return NoCatch("no material in the part's middle plane (x = 0)")
    if category == "two_point":
        return _bar(segments)
    if category == "knob":
        return _knob(segments)
    if category == "finger_pull":
        return _lip(segments, float(mesh.bounds[1][1]))
    raise RealIkeaError(f"unknown part category {category!r}")


@functools.lru_cache(maxsize=256)
def catch_features_at(path: str, category: str) -> CatchFeatures | NoCatch:
    """`catch_features` of a mesh file (e.g. a configuration's meshes/visual.obj), cached."""
    return catch_features(trimesh.load(path, force="mesh"), category)


# --------------------------------------------------------------------------------- the section


def _section_yz(mesh: trimesh.Trimesh) -> np.ndarray:
    """The mesh's section by the plane x = 0 as (n, 2, 2) segments in (y, z)."""
    lines = trimesh.intersections.mesh_plane(mesh, [1.0, 0.0, 0.0], [SECTION_X, 0.0, 0.0])
    return np.asarray(lines, dtype=float).reshape(-1, 2, 3)[:, :, 1:]


def _scan(segments: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Along each line z = const of the section: the lowest and the highest y of material (where
    the outline is crossed first and last; NaN where a line misses the section)."""
    (y0, z0), (y1, z1) = segments[:, 0].T, segments[:, 1].T
    t = z[:, None]
    hit = (np.minimum(z0, z1) <= t) & (t < np.maximum(z0, z1))  # half-open: vertices count once
    dz = np.where(z1 != z0, z1 - z0, 1.0)
    y = y0 + (t - z0) / dz * (y1 - y0)
    lowest = np.where(hit, y, np.inf).min(axis=1)
    highest = np.where(hit, y, -np.inf).max(axis=1)
    missed = ~hit.any(axis=1)
    lowest[missed], highest[missed] = np.nan, np.nan
    return lowest, highest


def _grid(top: float) -> np.ndarray:
    """Scan lines from just above the mounting plane to `top`, half a step off round values."""
    return np.arange(STEP / 2, max(top, STEP), STEP)


def _mm(value: float) -> str:
    return f"{value * 1e3:.1f} mm"


# --------------------------------------------------------------------------------- two-point


def _bar(segments: np.ndarray) -> BarCatch | NoCatch:
    """The section polygon holding the highest point at x = 0 is the bar."""
    points = segments.reshape(-1, 2)
    path = trimesh.load_path(np.column_stack([points, np.zeros(len(points))]).reshape(-1, 2, 3))
    planar, _ = path.to_2D(to_2D=np.eye(4))
    polygons = planar.polygons_full
    if not polygons:
        return NoCatch("the section of the part's middle (x = 0) is not closed")
    bar = max(polygons, key=lambda p: p.bounds[3])
    y0, z0, y1, z1 = bar.bounds
    if z0 < MIN_ROOM:
        return NoCatch(f"no gap behind the bar at the middle (x = 0): {_mm(z0)} < {_mm(MIN_ROOM)}")
    return BarCatch(proj=float(z1), height=float(y1 - y0), depth=float(z1 - z0))


# --------------------------------------------------------------------------------- knobs


def _knob(segments: np.ndarray) -> KnobCatch | NoCatch:
    z = _grid(float(segments[:, :, 1].max()))
    _, r = _scan(segments, z)
    r = np.where(np.isnan(r), -np.inf, r)
    radius = float(r.max())
    full = np.flatnonzero(r >= radius - FULL_RADIUS_TOL)
    j = int(full[-1])  # the full-radius band nearest the face: the head
    while j > 0 and r[j - 1] >= radius - FULL_RADIUS_TOL:
        j -= 1
    back = float(z[j] - STEP / 2)
    neck = float(r[:j].min()) if j > 0 else radius
    neck = max(neck, 0.0)
    undercut = radius - neck
    if undercut < MIN_ROOM:
        return NoCatch(f"no undercut behind the knob's head ({_mm(undercut)} < {_mm(MIN_ROOM)})")
    return KnobCatch(radius=radius, back=back, neck=neck)


# --------------------------------------------------------------------------------- finger pulls


def _lip(segments: np.ndarray, y_max: float) -> LipCatch | NoCatch:
    """Walk the z columns from the front back: the lip, the channel, the back wall."""
    z = _grid(float(segments[:, :, 1].max()))
    first, _ = _scan(segments, z)
    first = np.where(np.isnan(first), y_max, first)  # an empty column: open right through
    j = len(z) - 1
    edge_y = float(first[j])
    while j >= 0 and first[j] <= edge_y + LIP_RISE:
        edge_y = min(edge_y, float(first[j]))
        j -= 1
    if j < 0:
        return NoCatch("no channel behind a lip: nothing to get behind from below")
    edge_z = float(z[j] + STEP / 2)
    top = edge_y
    while j >= 0 and first[j] > edge_y + LIP_RISE:
        top = max(top, float(first[j]))
        j -= 1
    back = float(z[j] + STEP / 2) if j >= 0 else 0.0
    if top - edge_y < MIN_ROOM:
        return NoCatch(
            f"the lip hangs only {_mm(top - edge_y)} below its channel's roof (< {_mm(MIN_ROOM)})"
        )
    if edge_z - back < MIN_ROOM:
        return NoCatch(
            f"the channel behind the lip is only {_mm(edge_z - back)} wide (< {_mm(MIN_ROOM)})"
        )
    return LipCatch(edge_y=edge_y, edge_z=edge_z, back=back, top=top)
