"""Joint resistance felt at the handle: hinges scaled so a door resists a pull like a drawer.

The paper gives damping and friction for drawers (N s/m, N). Reusing those numbers as N m on a
hinge made a door's breakaway pull at its handle 3x a drawer's (58 N for a 40 cm door in high
mode, measured on the built library before this calibration). Here a hinge whose handle sits r
from its axis gets friction F r (N m) and damping c r^2 (N m s/rad): the handle then breaks away
at F newtons and is damped with c v newtons at handle speed v, exactly like a drawer of that mode.
"""

from __future__ import annotations

import numpy as np

# the resistance modes (realikea/conf/resistance/<name>.yaml), mildest first
MODES = ("smooth", "normal", "high")


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
