"""Step 4, collision generation: CoACD convex pieces and the single convex hull baseline."""

from __future__ import annotations

from dataclasses import dataclass

import coacd
import numpy as np
import trimesh


@dataclass(frozen=True)
class CoacdSettings:
    """CoACD parameters; `preprocess` 'auto' remeshes only inputs that are not watertight."""

    threshold: float = 0.05
    preprocess: str = "auto"
    preprocess_resolution: int = 50
    resolution: int = 2000
    max_convex_hull: int = -1
    mcts_iterations: int = 150
    mcts_max_depth: int = 3
    seed: int = 0


def coacd_pieces(mesh: trimesh.Trimesh, settings: CoacdSettings) -> list[trimesh.Trimesh]:
    """Approximate convex decomposition; watertight inputs skip CoACD's swelling remesh."""
    coacd.set_log_level("error")
    preprocess = settings.preprocess
    if preprocess == "auto":
        preprocess = "off" if mesh.is_watertight else "on"
    pieces = coacd.run_coacd(
        coacd.Mesh(np.asarray(mesh.vertices), np.asarray(mesh.faces)),
        threshold=settings.threshold,
        preprocess_mode=preprocess,
        preprocess_resolution=settings.preprocess_resolution,
        resolution=settings.resolution,
        max_convex_hull=settings.max_convex_hull,
        mcts_iterations=settings.mcts_iterations,
        mcts_max_depth=settings.mcts_max_depth,
        seed=settings.seed,
    )
    hulls = [trimesh.Trimesh(v, f).convex_hull for v, f in pieces]
    with np.errstate(invalid="ignore", divide="ignore"):  # flat slivers have no centre of mass
        return [h for h in hulls if h.volume > 1e-12]


def convex_hull(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """The single convex hull: the coarse collision shell most datasets ship."""
    return mesh.convex_hull
