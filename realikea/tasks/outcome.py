"""Fail / Partial / Success of an episode from its final joint opening (thresholds in config)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

OUTCOMES = ("fail", "partial", "success")


def outcome(opening, joint_type, thresholds: Mapping) -> np.ndarray:
    """Label each opening (m for slides, rad for hinges) with fail, partial or success."""
    opening = np.asarray(opening, dtype=float)
    joint_type = np.broadcast_to(np.asarray(joint_type), opening.shape)
    success = np.where(
        joint_type == "slide", thresholds["success"]["slide"], thresholds["success"]["hinge"]
    )
    partial = np.where(
        joint_type == "slide", thresholds["partial"]["slide"], thresholds["partial"]["hinge"]
    )
    return np.select([opening >= success, opening >= partial], ["success", "partial"], "fail")


def fractions(labels) -> dict[str, float]:
    """Fraction of episodes per outcome, in the fixed order fail, partial, success."""
    labels = np.asarray(labels)
    n = max(len(labels), 1)
    return {name: float(np.sum(labels == name)) / n for name in OUTCOMES}
