"""Step 1, component segmentation and formatting: one part's mesh, in metres, in the part frame."""

from __future__ import annotations

import numpy as np
import trimesh

from realikea.assets.catalog import Part
from realikea.assets.shapes import part_mesh
from realikea.errors import RealIkeaError


def formatted_components(part: Part) -> list[trimesh.Trimesh]:
    """The part's mesh split into connected components, each welded and consistently wound."""
    mesh = _source_mesh(part)
    mesh = trimesh.Trimesh(
        vertices=np.asarray(mesh.vertices, dtype=np.float64), faces=mesh.faces, process=True
    )
    mesh.remove_unreferenced_vertices()
    if len(mesh.faces) == 0:
        raise RealIkeaError(f"part {part.id!r}: mesh has no faces after formatting")
    components = mesh.split(only_watertight=False)
    for component in components:
        trimesh.repair.fix_normals(component)
    return sorted(components, key=lambda m: -abs(m.volume))


def _source_mesh(part: Part) -> trimesh.Trimesh:
    if part.mesh_file is not None:
        return trimesh.load_mesh(part.mesh_file, process=False)

    return part_mesh(part.family, part.dims)
