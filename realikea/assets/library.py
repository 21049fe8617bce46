"""Read a built library: its index and one configuration's MuJoCo model under a resistance mode."""

from __future__ import annotations

import csv
from pathlib import Path

import mujoco

from realikea.errors import RealIkeaError

FRONT_JOINT = "front_joint"


def read_index(library: Path) -> list[dict[str, str]]:
    """The rows of `index.csv`, one per configuration."""
    index = Path(library) / "index.csv"
    if not index.is_file():
        raise RealIkeaError(f"no index.csv in {library}; run `realikea assets build` first")
    with index.open(newline="") as f:
        return list(csv.DictReader(f))


def load_model(
    mjcf: Path, damping: float | None = None, frictionloss: float | None = None
) -> mujoco.MjModel:
    """Compile one configuration, optionally setting the front joint's resistance."""
    if not Path(mjcf).is_file():
        raise RealIkeaError(f"MJCF not found: {mjcf}")
    model = mujoco.MjModel.from_xml_path(str(mjcf))
    dof = model.jnt_dofadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, FRONT_JOINT)]
    if damping is not None:
        model.dof_damping[dof] = damping
    if frictionloss is not None:
        model.dof_frictionloss[dof] = frictionloss
    return model
