"""Load the visual mesh and the collision pieces from files, with errors that name the file.

A collision file may hold one convex piece or several: every object of a multi-object file (OBJ
``o`` groups, scene nodes of GLB/PLY/...) and every connected part of a mesh is one piece. Each
piece must be convex, because the metric (like MuJoCo) collides with the convex hull of a piece;
a non-convex piece is reported rather than silently replaced by its hull.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import trimesh
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from realikea.errors import RealIkeaError

# ratio of bounding-box diagonals collision/visual -> (collision units, visual units)
UNIT_FACTORS: dict[float, tuple[str, str]] = {
    1000.0: ("millimetres", "metres"),
    100.0: ("centimetres", "metres"),
    39.37: ("inches", "metres"),
    25.4: ("millimetres", "inches"),
    10.0: ("millimetres", "centimetres"),
    0.1: ("centimetres", "millimetres"),
    1 / 25.4: ("inches", "millimetres"),
    0.0254: ("metres", "inches"),
    0.01: ("metres", "centimetres"),
    0.001: ("metres", "millimetres"),
}
UNIT_MATCH = 0.10  # a ratio within 10 % of a factor is taken for that factor
SAME_SCALE = (0.5, 2.0)  # ratios inside this range are taken for the same units
PLAUSIBLE_METRES = (0.002, 5.0)  # bounding-box diagonal of a part or a base unit, metres
CONVEX_VOLUME_RATIO = 0.99  # piece volume / hull volume at or above this is convex


def _load_scene(path: str | Path, role: str) -> trimesh.Scene:
    path = Path(path)
    if not path.exists():
        raise RealIkeaError(f"{role} mesh {path}: no such file")
    if path.is_dir():
        raise RealIkeaError(f"{role} mesh {path}: is a directory, not a mesh file")
    try:
        loaded = trimesh.load(path, force="scene", process=False, split_objects=True)
    except Exception as err:  # trimesh raises many types for unreadable input
        raise RealIkeaError(f"{role} mesh {path}: not a readable mesh file ({err})") from err
    return loaded


def _triangle_meshes(path: Path, scene: trimesh.Scene, role: str) -> list[trimesh.Trimesh]:
    """The scene's triangle meshes, placed by their node transforms."""
    geoms = scene.dump(concatenate=False) if scene.geometry else []
    meshes = [g for g in geoms if isinstance(g, trimesh.Trimesh) and len(g.faces) > 0]
    if not meshes:
        other = sorted({type(g).__name__ for g in geoms if not isinstance(g, trimesh.Trimesh)})
        if other:
            raise RealIkeaError(
                f"{role} mesh {path}: not a triangle mesh (holds {', '.join(other)} only)"
            )
        raise RealIkeaError(f"{role} mesh {path}: empty mesh (no faces)")
    for mesh in meshes:
        if not np.all(np.isfinite(mesh.vertices)):
            raise RealIkeaError(f"{role} mesh {path}: has NaN or infinite vertex coordinates")
    return meshes


def load_visual(path: str | Path) -> trimesh.Trimesh:
    """The visual mesh P: every triangle mesh in the file, as one mesh (metres)."""
    path = Path(path)
    meshes = _triangle_meshes(path, _load_scene(path, "visual"), "visual")
    mesh = meshes[0] if len(meshes) == 1 else trimesh.util.concatenate(meshes)
    mesh.merge_vertices()
    mesh.metadata["path"] = str(path)
    return mesh


def _components(mesh: trimesh.Trimesh) -> list[trimesh.Trimesh]:
    """Connected parts of a mesh (sharing vertices after an exact positional merge)."""
    mesh = mesh.copy()
    mesh.merge_vertices()
    faces = mesh.faces
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]]])
    n = len(mesh.vertices)
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    count, labels = connected_components(graph, directed=False)
    if count == 1:
        return [mesh]
    face_label = labels[faces[:, 0]]
    parts = []
    for k in range(count):
        sel = np.flatnonzero(face_label == k)
        if len(sel):
            parts.append(mesh.submesh([sel], append=True))
    return parts


def load_pieces(path: str | Path) -> list[trimesh.Trimesh]:
    """The convex pieces stored in one collision file."""
    path = Path(path)
    meshes = _triangle_meshes(path, _load_scene(path, "collision"), "collision")
    pieces = [part for mesh in meshes for part in _components(mesh)]
    for k, piece in enumerate(pieces):
        _check_convex(piece, path, k, len(pieces))
        piece.metadata["path"] = str(path)
    return pieces


def _check_convex(piece: trimesh.Trimesh, path: Path, k: int, count: int) -> None:
    name = f"collision mesh {path}" + (f", piece {k + 1} of {count}," if count > 1 else "")
    if len(np.unique(piece.vertices, axis=0)) < 4:
        raise RealIkeaError(f"{name} has fewer than 4 distinct vertices: not a solid")
    try:
        hull = piece.convex_hull
    except Exception as err:
        raise RealIkeaError(f"{name} is flat (no volume): not a solid") from err
    if hull.volume <= 0.0:
        raise RealIkeaError(f"{name} is flat (no volume): not a solid")
    if not piece.is_watertight:
        return  # no volume to compare: the piece's hull is what collides
    ratio = abs(piece.volume) / hull.volume
    if ratio < CONVEX_VOLUME_RATIO:
        raise RealIkeaError(
            f"{name} is not convex (its volume is {ratio:.0%} of its convex hull's); "
            "a collision shell is a set of convex pieces: give each piece as its own file "
            "or object (e.g. the CoACD output), or its convex hull"
        )


def load_collision(paths: Sequence[str | Path]) -> list[trimesh.Trimesh]:
    """All convex pieces of all collision files."""
    if not paths:
        raise RealIkeaError("no collision mesh given")
    return [piece for path in paths for piece in load_pieces(path)]


def _diagonal(meshes: Sequence[trimesh.Trimesh]) -> float:
    lo = np.min([m.bounds[0] for m in meshes], axis=0)
    hi = np.max([m.bounds[1] for m in meshes], axis=0)
    return float(np.linalg.norm(hi - lo))


def _names(paths: Sequence[str | Path]) -> str:
    names = [str(p) for p in paths]
    return (
        ", ".join(names) if len(names) <= 3 else f"{', '.join(names[:3])} and {len(names) - 3} more"
    )


def _plausible_metres(diagonal: float) -> bool:
    """Whether a bounding-box diagonal is a plausible size in metres for a furniture part."""
    return PLAUSIBLE_METRES[0] <= diagonal <= PLAUSIBLE_METRES[1]


def check_units(
    visual: trimesh.Trimesh,
    pieces: Sequence[trimesh.Trimesh],
    visual_path: str | Path,
    collision_paths: Sequence[str | Path],
) -> None:
    """Raise if the collision pieces look like they are in other units than the visual mesh."""
    d_vis, d_col = _diagonal([visual]), _diagonal(pieces)
    if d_vis <= 0.0 or d_col <= 0.0:
        return
    ratio = d_col / d_vis
    if SAME_SCALE[0] <= ratio <= SAME_SCALE[1]:
        return
    col = _names(collision_paths)
    sizes = f"bounding-box diagonals {d_col:.6g} and {d_vis:.6g}"
    for factor, (col_unit, vis_unit) in UNIT_FACTORS.items():
        if abs(ratio / factor - 1.0) <= UNIT_MATCH:
            size = (
                f"about {factor:g} times the size of"
                if factor >= 1
                else f"about {1 / factor:.4g} times smaller than"
            )
            fix_collision = f"rescale the collision mesh by {1 / factor:.6g}"
            fix_visual = f"rescale the visual mesh by {factor:.6g}"
            if _plausible_metres(d_vis) and not _plausible_metres(d_col):
                fix = fix_collision
            elif _plausible_metres(d_col) and not _plausible_metres(d_vis):
                fix = fix_visual
            else:
                fix = f"{fix_collision} (or {fix_visual})"
            raise RealIkeaError(
                f"collision mesh {col} is {size} visual mesh {visual_path} ({sizes}): "
                f"looks like {col_unit} against {vis_unit}; {fix} so both are in metres"
            )
    raise RealIkeaError(
        f"collision mesh {col} is {ratio:.3g} times the size of visual mesh {visual_path} "
        f"({sizes}): not the same part or not the same units"
    )


def load_pair(
    visual_path: str | Path, collision_paths: Sequence[str | Path]
) -> tuple[trimesh.Trimesh, list[trimesh.Trimesh]]:
    """Visual mesh and collision pieces, checked to be in the same units."""
    visual = load_visual(visual_path)
    pieces = load_collision(collision_paths)
    check_units(visual, pieces, visual_path, collision_paths)
    return visual, pieces
