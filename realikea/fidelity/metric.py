"""Bidirectional surface deviation between a visual shell P and a collision shell Q.

The paper's metric (section "Closing the Contact-Geometry Gap"): sample points uniformly by area
on both shells; E(Q->P) is the mean distance from the collision shell's points to the visual
surface (outward "swelling"), E(P->Q) the symmetric one (visual surface the collision misses).

How it is computed here, and why it is exact:

* **The collision shell Q** is the outer boundary of the union of the convex pieces. Each piece
  is replaced by its convex hull (``Manifold.hull_points``; MuJoCo collides with the hull of a mesh
  geom anyway, and a CoACD piece already is one), and the hulls are united with manifold3d's
  exact boolean (``Manifold.batch_boolean(..., OpType.Add)``, symbolic perturbation for coplanar
  and touching faces, double precision out via ``to_mesh64``). Faces of a piece that lie inside
  another piece are therefore gone, not merely hidden.
* **Slits.** Real CoACD pieces that share a cut plane do not touch exactly: they leave slits a
  few micrometres wide (measured: up to 8 um on a 15 cm handle), and the exact union keeps both
  walls of every slit. On a CoACD bar handle those walls were 10 % (6 pieces) to 60 % (39 pieces)
  of the exact union's boundary area. They are not collision surface either, so a triangle of the
  union is dropped when the point ``tol`` beyond its centre along its outward normal lies inside
  one of the convex pieces, or less than ``tol / 2`` outside it (the slack catches a probe that
  lands in a sub-micrometre slit between two further pieces); inside is an exact half-space test
  against each piece's hull planes. This closes gaps narrower than ``tol`` = ``gap_tol`` x the
  shell's bounding-box diagonal (default 1e-4; on the CoACD handles and rings measured, the
  dropped area was the same to 0.02 % for any value from 2e-5 to 1e-3); wider gaps, which a
  finger could use, stay. Outer faces stay: moving outward leaves the solid. After closing, the
  shell of a 39-piece handle had the visual mesh's area to within 0.1 %. The decision is per
  triangle, by its centre; at a CoACD cut the two caps are the same cross-section, so a triangle
  half over a slit and half exposed only occurs at a slit's rim.
* **Sampling**: ``samples`` points per shell, face chosen with probability proportional to its
  area, then a uniform point in the triangle (square-root barycentric trick), from one seeded
  ``numpy.random.Generator``: the same seed gives the same points.
* **Distances** are exact point-to-triangle distances to the other shell's triangles, found with
  libigl's AABB tree (``igl.point_mesh_squared_distance``, double precision), not distances to
  the other shell's samples. The tree is built once per call; the queries run in C++.
  (``trimesh.proximity.closest_point`` is not used: besides being ~70x slower, its
  point-triangle routine uses an absolute tolerance that, at metre scale, misclassifies
  sub-millimetre triangles and returns distances up to 0.3 mm too large; see
  ``experiments/benchmarks/bench_fidelity.md``.)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import igl
import numpy as np
import trimesh
from manifold3d import Manifold, OpType
from scipy.spatial import ConvexHull, QhullError

from realikea.errors import RealIkeaError

DEFAULT_SAMPLES = 100_000
DEFAULT_GAP_TOL = 1e-4  # fraction of the shell's bounding-box diagonal


@dataclass(frozen=True)
class Deviation:
    """Distribution summary of one direction's point-to-surface distances (metres)."""

    mean: float
    median: float
    p90: float
    max: float

    @classmethod
    def of(cls, dist: np.ndarray) -> Deviation:
        """Summarise a distance array."""
        return cls(
            mean=float(np.mean(dist)),
            median=float(np.median(dist)),
            p90=float(np.percentile(dist, 90.0)),
            max=float(np.max(dist)),
        )

    def to_dict(self) -> dict:
        return {"mean": self.mean, "median": self.median, "p90": self.p90, "max": self.max}


@dataclass(frozen=True)
class FidelityResult:
    """Both directions of the deviation, plus the samples and distances for heat maps."""

    q_to_p: Deviation
    p_to_q: Deviation
    q_points: np.ndarray
    q_dist: np.ndarray
    p_points: np.ndarray
    p_dist: np.ndarray

    def to_dict(self) -> dict:
        """``{"q_to_p": {mean, median, p90, max}, "p_to_q": {...}}`` in metres."""
        return {"q_to_p": self.q_to_p.to_dict(), "p_to_q": self.p_to_q.to_dict()}


def _hull_planes(vertices: np.ndarray) -> np.ndarray | None:
    """Outward unit half-space equations (n, d) with n.x + d <= 0 inside; None if flat."""
    try:
        return ConvexHull(vertices).equations
    except QhullError:
        return None


def _inside(points: np.ndarray, planes: np.ndarray, slack: float, chunk: int = 64) -> np.ndarray:
    """Mask of points less than ``slack`` outside every half-space (drops a point at the first
    plane it is beyond)."""
    alive = np.arange(len(points))
    for start in range(0, len(planes), chunk):
        eq = planes[start : start + chunk]
        alive = alive[(points[alive] @ eq[:, :3].T + eq[:, 3]).max(axis=1) < slack]
        if len(alive) == 0:
            break
    mask = np.zeros(len(points), dtype=bool)
    mask[alive] = True
    return mask


def collision_shell(
    pieces: Sequence[trimesh.Trimesh], gap_tol: float | None = DEFAULT_GAP_TOL
) -> trimesh.Trimesh:
    """Outer boundary of the union of the convex pieces (see the module docstring).

    ``gap_tol`` is a fraction of the bounding-box diagonal; slits between pieces narrower than that
    are closed (``None`` or 0 keeps the exact union). ``metadata`` of the result records
    ``pieces``, ``crack_faces`` and ``crack_area`` (the dropped slit walls).
    """
    if len(pieces) == 0:
        raise RealIkeaError("collision shell: no convex pieces given")
    hulls, planes = [], []
    for k, piece in enumerate(pieces):
        verts = np.asarray(piece.vertices, dtype=np.float64)
        if len(verts) < 4:
            raise RealIkeaError(f"collision piece {k}: fewer than 4 vertices, not a solid")
        hull = Manifold.hull_points(verts)
        if hull.is_empty() or hull.volume() <= 0.0:
            raise RealIkeaError(f"collision piece {k}: flat (zero volume), not a solid")
        hulls.append(hull)
        planes.append(_hull_planes(verts))
    union = hulls[0] if len(hulls) == 1 else Manifold.batch_boolean(hulls, OpType.Add)
    mesh64 = union.to_mesh64()
    shell = trimesh.Trimesh(
        np.array(mesh64.vert_properties[:, :3], dtype=np.float64),
        np.array(mesh64.tri_verts, dtype=np.int64),
        process=False,
    )
    crack = np.zeros(len(shell.faces), dtype=bool)
    if gap_tol and len(hulls) > 1:
        diag = float(np.linalg.norm(np.ptp(shell.vertices, axis=0)))
        tol = gap_tol * diag
        probe = shell.triangles_center + shell.face_normals * tol
        for eq, piece in zip(planes, pieces, strict=True):
            if eq is None:
                continue
            bmin, bmax = piece.bounds
            box = np.all((probe >= bmin - tol) & (probe <= bmax + tol), axis=1)
            near = np.flatnonzero(box & ~crack)
            if len(near) == 0:
                continue
            crack[near[_inside(probe[near], eq, tol / 2)]] = True
    crack_area = float(shell.area_faces[crack].sum())
    if crack.any():
        shell = trimesh.Trimesh(shell.vertices, shell.faces[~crack], process=False)
        shell.remove_unreferenced_vertices()
    shell.metadata.update(pieces=len(pieces), crack_faces=int(crack.sum()), crack_area=crack_area)
    return shell


def sample_surface(mesh: trimesh.Trimesh, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` points uniformly distributed by area on the mesh's triangles."""
    tri = np.asarray(mesh.triangles, dtype=np.float64)
    area = np.asarray(mesh.area_faces, dtype=np.float64)
    cdf = np.cumsum(area)
    if cdf[-1] <= 0.0:
        raise RealIkeaError("cannot sample a surface of zero area")
    face = np.searchsorted(cdf, rng.random(count) * cdf[-1], side="right")
    face = np.minimum(face, len(area) - 1)
    r1 = np.sqrt(rng.random(count))
    r2 = rng.random(count)
    a, b, c = tri[face, 0], tri[face, 1], tri[face, 2]
    return a * (1.0 - r1)[:, None] + b * (r1 * (1.0 - r2))[:, None] + c * (r1 * r2)[:, None]


def point_surface_distance(points: np.ndarray, mesh: trimesh.Trimesh) -> np.ndarray:
    """Exact Euclidean distance from each point to the nearest triangle of ``mesh``."""
    sq, _, _ = igl.point_mesh_squared_distance(
        np.ascontiguousarray(points, dtype=np.float64),
        np.ascontiguousarray(mesh.vertices, dtype=np.float64),
        np.ascontiguousarray(mesh.faces, dtype=np.int64),
    )
    return np.sqrt(np.maximum(sq, 0.0))


def surface_deviation(
    visual: trimesh.Trimesh,
    pieces: Sequence[trimesh.Trimesh],
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    gap_tol: float | None = DEFAULT_GAP_TOL,
) -> FidelityResult:
    """E(Q->P) and E(P->Q) between the visual mesh and the union of the convex pieces."""
    if samples < 1:
        raise RealIkeaError(f"samples must be at least 1, got {samples}")
    if len(visual.faces) == 0:
        raise RealIkeaError("visual mesh has no faces")
    shell = collision_shell(pieces, gap_tol=gap_tol)
    rng = np.random.default_rng(seed)
    q_points = sample_surface(shell, samples, rng)
    p_points = sample_surface(visual, samples, rng)
    q_dist = point_surface_distance(q_points, visual)
    p_dist = point_surface_distance(p_points, shell)
    return FidelityResult(
        q_to_p=Deviation.of(q_dist),
        p_to_q=Deviation.of(p_dist),
        q_points=q_points,
        q_dist=q_dist,
        p_points=p_points,
        p_dist=p_dist,
    )
