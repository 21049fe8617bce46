"""The fidelity report's heat maps: which parts to show and the distance fields on their
triangles, split fine enough to show where the collision mesh swells."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from realikea.assets.catalog import CATEGORIES
from realikea.fidelity.measure import PartJob
from realikea.fidelity.meshes import load_pair
from realikea.fidelity.metric import (
    collision_shell,
    point_surface_distance,
)

HEAT_EDGES = 60  # heat-map triangles are split to edges under (bounding-box diagonal / this)
HEAT_TRIANGLES = 60_000  # ... unless that gives more triangles than this per panel


@dataclass
class HeatPanel:
    """Triangles to draw (n x 3 x 3, metres) and the value at each (None: draw plain)."""

    title: str
    triangles: np.ndarray
    values: np.ndarray | None
    mean: float | None = None  # the metric's mean for this field (metres)


@dataclass
class HeatRow:
    """The four panels of one part: P, dist(p, Q), dist(q, P) on CoACD, dist(q', P) on the hull."""

    part_id: str
    family: str
    label: str
    panels: list[HeatPanel]


def split_triangles(
    triangles: np.ndarray, max_edge: float, limit: int | None = None
) -> np.ndarray | None:
    """Bisect each triangle's longest edge until no edge is longer than ``max_edge``.

    Each triangle is split on its own (the result has T-junctions, harmless for drawing), so a
    long sliver becomes a row of pieces instead of the 4^k of midpoint subdivision. Winding is
    kept. Returns None as soon as the result would exceed ``limit`` triangles.
    """
    done = []
    tris = np.asarray(triangles, dtype=np.float64)
    while len(tris):
        if limit is not None and sum(map(len, done)) + len(tris) > limit:
            return None
        edges = np.linalg.norm(tris[:, [1, 2, 0]] - tris, axis=2)  # edge k runs k -> k+1
        long = edges.max(axis=1) > max_edge
        done.append(tris[~long])
        tris, k = tris[long], edges[long].argmax(axis=1)
        order = (np.arange(3)[None, :] + k[:, None]) % 3  # rotate: the longest edge is 0 -> 1
        t = np.take_along_axis(tris, order[:, :, None], axis=1)
        mid = (t[:, 0] + t[:, 1]) / 2
        tris = np.concatenate(
            [np.stack([t[:, 0], mid, t[:, 2]], axis=1), np.stack([mid, t[:, 1], t[:, 2]], axis=1)]
        )
    return np.concatenate(done)


def split_within(triangles: np.ndarray, max_edge: float, budget: int) -> np.ndarray:
    """``split_triangles`` at the finest edge length from ``max_edge`` up that fits ``budget``."""
    triangles = np.asarray(triangles, dtype=np.float64)
    if len(triangles) >= budget:
        return triangles
    while (tris := split_triangles(triangles, max_edge, budget)) is None:
        max_edge *= 1.4
    return tris


def heat_row(
    job: PartJob,
    row: dict,
    label: str,
    edges: int = HEAT_EDGES,
    budget: int = HEAT_TRIANGLES,
) -> HeatRow:
    """Distance fields on the shells of one part, one value per (split) triangle's centre."""
    visual, coacd = load_pair(job.meshes.visual, job.meshes.pieces["coacd"])
    _, hull = load_pair(job.meshes.visual, job.meshes.pieces["hull"])
    q, q_hull = collision_shell(coacd), collision_shell(hull)
    max_edge = float(np.linalg.norm(np.ptp(q_hull.vertices, axis=0))) / edges

    def panel(mesh: trimesh.Trimesh, other: trimesh.Trimesh, title: str, mean: float) -> HeatPanel:
        tris = split_within(mesh.triangles, max_edge, budget)
        dist = point_surface_distance(tris.mean(axis=1), other)
        return HeatPanel(title, tris.astype(np.float32), dist.astype(np.float32), mean)

    return HeatRow(
        job.part_id,
        job.family,
        label,
        [
            HeatPanel("visual mesh P", np.asarray(visual.triangles, dtype=np.float32), None),
            panel(visual, q, "dist(p, Q) on P, CoACD", row["coacd_p_to_q_mean_m"]),
            panel(q, visual, "dist(q, P) on Q, CoACD", row["coacd_q_to_p_mean_m"]),
            panel(q_hull, visual, "dist(q', P) on Q', hull", row["hull_q_to_p_mean_m"]),
        ],
    )


def _exposed_swelling(row: dict) -> float:
    value = row.get("coacd_q_to_p_mean_exposed_m", float("nan"))
    return row["coacd_q_to_p_mean_m"] if np.isnan(value) else value


def heatmap_parts(rows: list[dict], per_category: int) -> dict[str, list[tuple[dict, str]]]:
    """Per category, ``per_category`` parts spread from the median to the worst CoACD swelling.

    Ranked by CoACD's E(Q->P) over the exposed surface (without the mounting cap: it is one mount
    clearance off for every part and hidden against the front). With one part, the typical
    (median) one; with more, the last is the worst, so the heat maps show both what CoACD
    usually achieves and where it is weakest. Between them a new family is preferred.
    """
    chosen: dict[str, list[tuple[dict, str]]] = {}
    for category in CATEGORIES:
        ranked = sorted((r for r in rows if r["category"] == category), key=_exposed_swelling)
        n, k = len(ranked), min(per_category, len(ranked))
        if k == 0:
            continue
        mid = (n - 1) // 2
        targets = [mid] if k == 1 else [round(t) for t in np.linspace(mid, n - 1, k)]
        picked: list[int] = []
        for i, target in enumerate(targets):
            free = sorted((j for j in range(n) if j not in picked), key=lambda j: abs(j - target))
            if k > 1 and i == k - 1:
                j = free[0]  # the worst (or the nearest still free)
            else:
                families = {ranked[p]["family"] for p in picked}
                j = next((j for j in free if ranked[j]["family"] not in families), free[0])
            picked.append(j)
        picks = []
        for j in picked:
            rank = f"rank {j + 1}/{n}"
            kind = "worst CoACD" if j == n - 1 and n > 1 else "typical" if j == mid else ""
            picks.append((ranked[j], f"{kind}, {rank}" if kind else rank))
        chosen[category] = picks
    return chosen
