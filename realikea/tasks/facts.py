"""What a scripted policy may know of an episode's scene: privileged geometry in the world frame."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SceneFacts:
    """One episode's scene as it stands after reset (poses include the randomization).

    Observations hold positions relative to the robot base; `robot_base` converts them.
    """

    config_id: str
    part_id: str
    category: str  # knob, two_point or finger_pull
    base_kind: str  # drawer, door or flap
    joint_type: str  # slide or hinge
    robot_base: np.ndarray  # (3,) world position of the robot's base link
    handle_pos: np.ndarray  # (3,) the handle site: just below the part's top surface
    part_pos: np.ndarray  # (3,) origin of the part frame (the mount point on the front)
    part_rot: np.ndarray  # (3, 3) part frame axes as columns; z points out of the front
    pull_dir: np.ndarray  # (3,) unit direction the handle moves as the front opens
    hinge_anchor: np.ndarray | None  # (3,) a point on the hinge axis (hinges only)
    hinge_axis: np.ndarray | None  # (3,) unit; opening turns positively about it
    visual_mesh: str  # the part's visual mesh (part frame, metres)
    tcp_nominal: np.ndarray  # (3, 3) the TCP orientation at pitch 0 (roll fixed per scene)
    pad_friction: float = 1.0
    max_aperture: float = 0.08  # m between the open jaws

    def to_part(self, points) -> np.ndarray:
        """World points (..., 3) in the part frame."""
        return (np.asarray(points) - self.part_pos) @ self.part_rot

    def to_world(self, points) -> np.ndarray:
        """Part-frame points (..., 3) in the world frame."""
        return np.asarray(points) @ self.part_rot.T + self.part_pos
