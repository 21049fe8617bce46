"""Per-episode perturbation of handle and base poses, and the two-phase schedule."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from omegaconf import DictConfig

from realikea.errors import RealIkeaError

POSE_MODES = ("fixed", "randomized", "two_phase")


@dataclass(frozen=True)
class Randomization:
    """Bounds of the uniform pose perturbations and when they are on."""

    mode: str
    switch_iteration: int
    handle_pos: np.ndarray  # (3,) m: along the front normal, across, up
    base_pos: np.ndarray  # (3,) m
    base_yaw: float  # rad

    @classmethod
    def from_config(cls, dr: DictConfig) -> Randomization:
        if dr.mode not in POSE_MODES:
            raise RealIkeaError(f"dr.mode={dr.mode!r}: use one of {', '.join(POSE_MODES)}")
        return cls(
            str(dr.mode),
            int(dr.switch_iteration),
            np.asarray(dr.handle.pos, float),
            np.asarray(dr.base.pos, float),
            float(np.radians(dr.base.yaw_deg)),
        )

    def active(self, iteration: int) -> bool:
        """Whether poses are perturbed at this training iteration."""
        return self.mode == "randomized" or (
            self.mode == "two_phase" and iteration >= self.switch_iteration
        )


def two_phase_switch(dr: DictConfig | dict | None) -> int | None:
    """The iteration a two-phase schedule switches to randomized poses; None for other modes."""
    dr = dr or {}
    return int(dr["switch_iteration"]) if dr.get("mode") == "two_phase" else None


class PosePerturbation:
    """Applies sampled offsets to one compiled scene, always relative to its nominal poses.

    The handle offset moves the part's own body (welded to the front, see the assembly step),
    so its geoms, their collision bounds and the handle site move together.
    """

    def __init__(self, model: mujoco.MjModel, part_body: int, root: int):
        self.model, self.part_body, self.root = model, part_body, root
        self.part_pos = model.body_pos[part_body].copy()
        self.root_pos = model.body_pos[root].copy()
        self.root_quat = model.body_quat[root].copy()

    def apply(self, rng: np.random.Generator | None, bounds: Randomization) -> None:
        """Sample and apply offsets, or restore the nominal poses when `rng` is None."""
        handle = np.zeros(3) if rng is None else rng.uniform(-1, 1, 3) * bounds.handle_pos
        base = np.zeros(3) if rng is None else rng.uniform(-1, 1, 3) * bounds.base_pos
        yaw = 0.0 if rng is None else rng.uniform(-1, 1) * bounds.base_yaw
        self.model.body_pos[self.part_body] = self.part_pos + handle
        self.model.body_pos[self.root] = self.root_pos + base
        turn = np.array([np.cos(yaw / 2), 0.0, 0.0, np.sin(yaw / 2)])
        quat = np.empty(4)
        mujoco.mju_mulQuat(quat, turn, self.root_quat)
        self.model.body_quat[self.root] = quat
