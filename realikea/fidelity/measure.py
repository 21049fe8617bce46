"""Measuring one part for the fidelity report (runs in a worker process): both collision sources
against the visual mesh, E(Q->P) and E(P->Q) statistics, mesh counts and face areas."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from realikea.assets.build import (
    PartMeshes,
)
from realikea.fidelity.meshes import load_pair
from realikea.fidelity.metric import (
    surface_deviation,
)
from realikea.sources import SOURCES

STATS = ("mean", "median", "p90", "max")
DIRECTIONS = ("q_to_p", "p_to_q")
MM = 1000.0
MOUNT_TOL = 1e-5  # m: samples this close to the mounting plane (P) or clip plane (Q) are on it

COLUMNS = (
    "id",
    "category",
    "family",
    "visual_vertices",
    "visual_faces",
    *(
        f"{src}_{col}"
        for src in SOURCES
        for col in (
            "pieces",
            "vertices",
            "faces",
            *(f"{d}_{s}_m" for d in DIRECTIONS for s in STATS),
            *(f"{d}_mean_exposed_m" for d in DIRECTIONS),
        )
    ),
)


@dataclass(frozen=True)
class PartJob:
    """Everything a worker needs to measure one part."""

    part_id: str
    category: str
    family: str
    meshes: PartMeshes
    samples: int
    seed: int
    mount_clearance: float  # the collision input is clipped at z = this (workflow step 3)


@dataclass
class PartResult:
    """One part's CSV row plus the face areas of its meshes (m^2, for the mesh statistics)."""

    row: dict
    face_areas: dict[str, np.ndarray] = field(default_factory=dict)


def measure_part(job: PartJob) -> PartResult:
    """Both collision sources of one part against its visual mesh."""
    row: dict = {"id": job.part_id, "category": job.category, "family": job.family}
    areas: dict[str, np.ndarray] = {}
    visual = None
    for src in SOURCES:
        visual, pieces = load_pair(job.meshes.visual, job.meshes.pieces[src])
        result = surface_deviation(visual, pieces, samples=job.samples, seed=job.seed)
        row[f"{src}_pieces"] = len(pieces)
        row[f"{src}_vertices"] = sum(len(p.vertices) for p in pieces)
        row[f"{src}_faces"] = sum(len(p.faces) for p in pieces)
        for direction, dev in (("q_to_p", result.q_to_p), ("p_to_q", result.p_to_q)):
            for stat in STATS:
                row[f"{src}_{direction}_{stat}_m"] = getattr(dev, stat)
        # the same means over the exposed surface only: without the face screwed to the front
        # (z = 0 on P) and the collision shell's cap on the clip plane (z = mount clearance)
        q_free = result.q_points[:, 2] > job.mount_clearance + MOUNT_TOL
        p_free = result.p_points[:, 2] > MOUNT_TOL
        row[f"{src}_q_to_p_mean_exposed_m"] = _mean_or_nan(result.q_dist[q_free])
        row[f"{src}_p_to_q_mean_exposed_m"] = _mean_or_nan(result.p_dist[p_free])
        areas[src] = np.concatenate([p.area_faces for p in pieces]).astype(np.float32)
    assert visual is not None
    row["visual_vertices"] = len(visual.vertices)
    row["visual_faces"] = len(visual.faces)
    areas["visual"] = visual.area_faces.astype(np.float32)
    return PartResult({k: row[k] for k in COLUMNS}, areas)


def _mean_or_nan(values: np.ndarray) -> float:
    return float(values.mean()) if len(values) else float("nan")
