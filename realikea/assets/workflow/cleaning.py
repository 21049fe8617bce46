"""Step 2, structural cleaning: drop internal shells, fuse components, fill blind mounting bores.

Internal features (hidden shells, screw bores opening only on the mounting face) would turn
into convex pieces that collide with the front they are screwed to; the exterior surfaces a
hand touches are kept exactly.
"""

from __future__ import annotations

import manifold3d as m3
import numpy as np
import shapely
import trimesh

from realikea.errors import RealIkeaError

SECTION_HEIGHT = 2e-4  # m above the mounting plane where bore openings are found
BORE_OVERLAP = 2e-4  # m the filling plug reaches past the bore bottom into solid material


def to_manifold(mesh: trimesh.Trimesh) -> m3.Manifold:
    """Convert a watertight trimesh into a manifold3d solid."""
    solid = m3.Manifold(
        m3.Mesh64(
            vert_properties=np.array(mesh.vertices, dtype=np.float64, order="C"),
            tri_verts=np.array(mesh.faces, dtype=np.uint64, order="C"),
        )
    )
    if solid.status() != m3.Error.NoError:
        raise RealIkeaError(f"mesh is not a closed solid ({solid.status().name})")
    return solid


def to_trimesh(solid: m3.Manifold) -> trimesh.Trimesh:
    """Convert a manifold3d solid back to a trimesh, keeping its (manifold) vertex topology."""
    mesh = solid.to_mesh64()
    vertices, faces = np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts)
    return trimesh.Trimesh(vertices, faces, process=False)


def cleaned_solid(components: list[trimesh.Trimesh]) -> trimesh.Trimesh:
    """One watertight solid without internal shells or blind bores on the mounting face."""
    outer = [c for c in components if c.is_watertight and c.volume > 0]
    if not outer:
        raise RealIkeaError("mesh has no closed, outward-facing component (is it watertight?)")
    outer = [c for i, c in enumerate(outer) if not _enclosed_by_any(c, outer[:i])]
    solid = m3.Manifold.batch_boolean([to_manifold(c) for c in outer], m3.OpType.Add)
    solid = fill_mounting_bores(solid)
    return to_trimesh(solid)


def _enclosed_by_any(inner: trimesh.Trimesh, others: list[trimesh.Trimesh]) -> bool:
    return any(other.contains(inner.vertices).all() for other in others)


def fill_mounting_bores(solid: m3.Manifold) -> m3.Manifold:
    """Plug every blind hole that opens only on the mounting plane z = 0."""
    mesh = to_trimesh(solid)
    plugs = [
        m3.Manifold.extrude(
            m3.CrossSection([np.asarray(ring.coords)[:-1]], m3.FillRule.NonZero),
            depth + BORE_OVERLAP,
        )
        for ring, depth in _blind_openings(mesh)
    ]
    return m3.Manifold.batch_boolean([solid, *plugs], m3.OpType.Add) if plugs else solid


def _blind_openings(mesh: trimesh.Trimesh):
    """(ring, depth) for each hole in the near-mounting section that is closed further up."""
    section = mesh.section(plane_origin=[0, 0, SECTION_HEIGHT], plane_normal=[0, 0, 1])
    if section is None:
        return
    planar, _ = section.to_2D(to_2D=np.eye(4))
    for polygon in planar.polygons_full:
        for ring in polygon.interiors:
            hole = shapely.Polygon(ring)
            probe = hole.representative_point()
            origin = np.array([[probe.x, probe.y, SECTION_HEIGHT]])
            hits, _, faces = mesh.ray.intersects_location(origin, np.array([[0.0, 0.0, 1.0]]))
            if len(hits) == 0:
                continue  # a through-hole: real geometry, keep it
            first = np.argmin(hits[:, 2])
            if mesh.face_normals[faces[first], 2] < 0:  # the bore's ceiling faces the opening
                yield shapely.Polygon(hole.exterior).buffer(1e-5).exterior, hits[first, 2]
