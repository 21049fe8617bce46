"""Joint resistance felt at the handle: hinges scaled so a door resists a pull like a drawer.

The paper gives damping and friction for drawers (N s/m, N). Reusing those numbers as N m on a
hinge made a door's breakaway pull at its handle 3x a drawer's (58 N for a 40 cm door in high
mode, measured on the built library before this calibration). Here a hinge whose handle sits r
from its axis gets friction F r (N m) and damping c r^2 (N m s/rad): the handle then breaks away
at F newtons and is damped with c v newtons at handle speed v, exactly like a drawer of that mode.

A mode is applied in two places only: where a scene is built (`realikea/sim/scene.py`) and where a
configuration is exported (`realikea/export/`). The built library is written once at the nominal
mode and no run rewrites it, so its MJCF files are the same whatever mode a run uses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from omegaconf import DictConfig, OmegaConf

from realikea.config import config_number
from realikea.errors import RealIkeaError
from realikea.files import CONF_DIR

# the resistance modes (realikea/conf/resistance/<name>.yaml), mildest first
MODES = ("smooth", "normal", "high")
NOMINAL = "normal"  # the mode the built library's MJCF files carry (the config's default)


@dataclass(frozen=True)
class Resistance:
    """Joint damping and friction loss of one resistance mode, at the handle (a drawer's units)."""

    name: str
    damping: float
    frictionloss: float

    @classmethod
    def from_config(cls, cfg: DictConfig) -> Resistance:
        """The `resistance` group of a composed config, each value checked."""
        r = cfg.resistance
        return cls(
            str(r.name),
            config_number(r, "damping", "resistance.damping", minimum=0.0),
            config_number(r, "frictionloss", "resistance.frictionloss", minimum=0.0),
        )


def mode(name: str) -> Resistance:
    """One named mode as its config file gives it; an unknown name lists the modes."""
    if name not in MODES:
        raise RealIkeaError(f"unknown resistance mode {name!r}; choose one of {', '.join(MODES)}")
    node = OmegaConf.load(CONF_DIR / "resistance" / f"{name}.yaml")
    return Resistance.from_config(OmegaConf.create({"resistance": node}))


def modes() -> list[Resistance]:
    """Every mode, mildest first."""
    return [mode(name) for name in MODES]


def nominal() -> Resistance:
    """The mode the built library is written at."""
    return mode(NOMINAL)


def lever_arm(anchor, axis, point) -> float:
    """Distance (m) from `point` to the line through `anchor` along `axis`."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    offset = np.asarray(point, float) - np.asarray(anchor, float)
    return float(np.linalg.norm(offset - offset.dot(axis) * axis))


def handle_resistance(
    joint_type: str, lever: float, damping: float, frictionloss: float
) -> tuple[float, float]:
    """(damping, frictionloss) of the joint for a mode's drawer values and the handle's lever
    arm: a slide as given, a hinge scaled by r^2 and r."""
    if joint_type == "slide":
        return damping, frictionloss
    if lever <= 0:
        raise ValueError(f"a hinge needs a positive lever arm to its handle, got {lever}")
    return damping * lever**2, frictionloss * lever
