"""Step 3, pre-collision scaling and clipping of the tightly fitted regions.

Two regions fit tightly: the part's mounting face against the front, and the moving front
inside its carcass. Decomposition swelling at either would jam the front against its frame,
so the part's collision input is clipped a clearance in front of the mounting plane and the
front's collision box is inset from its visual outline by a clearance on every side.
"""

from __future__ import annotations

import numpy as np
import trimesh

from realikea.assets.workflow.cleaning import to_manifold, to_trimesh
from realikea.errors import RealIkeaError


def clipped_for_collision(solid: trimesh.Trimesh, mount_clearance: float) -> trimesh.Trimesh:
    """The part solid cut at z = mount_clearance, keeping the side away from the front."""
    clipped = to_manifold(solid).trim_by_plane([0.0, 0.0, 1.0], mount_clearance)
    if clipped.is_empty():
        raise RealIkeaError(
            f"nothing of the part lies beyond the mount clearance {mount_clearance}"
        )
    return to_trimesh(clipped)


def inset_half_extents(half_extents: np.ndarray, clearance: float) -> np.ndarray:
    """Half-extents of a front's collision box, inset by `clearance` in its plane (y, z)."""
    inset = np.asarray(half_extents, dtype=float) - np.array([0.0, clearance, clearance])
    if np.any(inset <= 0):
        raise RealIkeaError(f"front clearance {clearance} m leaves no front to collide with")
    return inset
