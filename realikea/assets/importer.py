"""Bring your own part: a scanned or CAD mesh joins the catalog through the same workflow.

The mesh must be in the part frame convention (the catalog's: +z away from the furniture front, long
axis along x); it is moved so its lowest point lies on the mounting plane z = 0 and its
footprint is centred on the mounting point, then checked by running steps 1-4 on it.
"""

from __future__ import annotations

import json
import re
import tempfile
from pathlib import Path

import numpy as np
import trimesh
from omegaconf import DictConfig

from realikea.assets.build import WorkflowSettings, write_part_meshes
from realikea.assets.catalog import CATEGORIES, FRICTION_CLASSES, Catalog, Part, imported_dir
from realikea.errors import RealIkeaError
from realikea.files import staging_dir

MIN_EXTENT, MAX_EXTENT = 0.005, 0.5  # m: plausible size range of furniture hardware
MESH_SUFFIXES = (".obj", ".stl", ".ply", ".glb", ".gltf", ".off")


def load_user_mesh(path: Path, scale: float = 1.0) -> trimesh.Trimesh:
    """Read one mesh file (scenes are concatenated) and check it is a plausible solid part."""
    if not path.is_file():
        raise RealIkeaError(f"mesh file not found: {path}")
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise RealIkeaError(f"{path}: not a mesh file (expected one of {', '.join(MESH_SUFFIXES)})")
    try:
        mesh = trimesh.load(path, force="mesh", process=True)
    except Exception as err:  # trimesh raises many types for unreadable files
        raise RealIkeaError(f"{path}: cannot be read as a mesh ({err})") from err
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise RealIkeaError(f"{path}: contains no triangles")
    mesh.apply_scale(scale)
    extent = float(np.max(mesh.extents))
    if extent > MAX_EXTENT:
        hint = " (millimetres? try --scale 0.001)" if extent * 1e-3 >= MIN_EXTENT else ""
        raise RealIkeaError(f"{path}: implausible size {extent:g} m for a handle or knob{hint}")
    if extent < MIN_EXTENT:
        raise RealIkeaError(f"{path}: implausible size {extent:g} m for a handle or knob")
    if not mesh.is_watertight:
        raise RealIkeaError(
            f"{path}: mesh is not watertight (open boundary or non-manifold edges); "
            "repair it into a closed solid first"
        )
    if mesh.volume <= 1e-12 or len(mesh.nondegenerate_faces()) < 4:
        raise RealIkeaError(f"{path}: degenerate mesh (no enclosed volume)")
    return mesh


def to_part_frame(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Put the lowest point on z = 0 and centre the footprint on the mounting point."""
    lo, hi = mesh.bounds
    mesh = mesh.copy()
    mesh.apply_translation([-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]])
    return mesh


def import_part(
    path: Path,
    category: str,
    part_id: str | None,
    scale: float,
    friction: str,
    cfg: DictConfig,
    root: Path | None = None,
) -> Part:
    """Validate, format and register a user mesh under `imported_dir(root)/<id>/`."""
    if category not in CATEGORIES:
        raise RealIkeaError(f"unknown category {category!r}; choose one of {', '.join(CATEGORIES)}")
    if friction not in FRICTION_CLASSES:
        raise RealIkeaError(
            f"unknown friction class {friction!r}; one of {', '.join(FRICTION_CLASSES)}"
        )
    part_id = part_id or re.sub(r"[^a-z0-9_]+", "_", path.stem.lower()).strip("_")
    if not re.fullmatch(r"[a-z0-9_]+", part_id or ""):
        raise RealIkeaError(f"part id {part_id!r} must be lowercase letters, digits and _")
    if part_id in Catalog.load(root).parts:
        raise RealIkeaError(f"part id {part_id!r} already exists in the catalog; pass --id NAME")
    mesh = to_part_frame(load_user_mesh(path, scale))
    with staging_dir(imported_dir(root) / part_id) as folder:
        mesh.export(folder / "mesh.ply")
        meta = {
            "id": part_id,
            "category": category,
            "friction": friction,
            "source": str(path),
            "scale": scale,
        }
        (folder / "part.json").write_text(json.dumps(meta, indent=1))
        part = Part(part_id, category, "imported", friction, {}, folder / "mesh.ply")
        with tempfile.TemporaryDirectory() as check:
            write_part_meshes(part, WorkflowSettings.from_config(cfg), Path(check))
    return Catalog.load(root).part(part_id)
