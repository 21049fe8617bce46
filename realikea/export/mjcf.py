"""MJCF: the built model file of one collision source, copied with exactly the meshes it uses."""

from __future__ import annotations

import shutil
from pathlib import Path

from realikea.export.model import Articulation, link_mesh_files

RESISTANCE_SCHEMA = (
    "MJCF <joint damping frictionloss/> as built (slide: N s/m and N; hinge: N m s/rad and N m), "
    "friction loss with solreffriction/solimpfriction"
)


def write_mjcf(articulation: Articulation, folder: Path, name: str) -> Path:
    """Copy the built MJCF to `folder/name`, its meshes to the same relative paths."""
    link_mesh_files(articulation, folder)
    shutil.copyfile(articulation.mjcf, folder / name)
    return folder / name
