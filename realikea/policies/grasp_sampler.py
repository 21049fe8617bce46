"""`grasp_sampler`: execute the best antipodal grasp sampled on the part's visual mesh
(`realikea/policies/grasp_sampling.py`) or read from a grasp file
(`realikea/policies/grasp_files.py`): jaws open at a pregrasp `pregrasp` m back along the
approach axis, advance onto the grasp, close, then pull along the front's opening path
(`pull_waypoints`: straight on a slide, the arc on a hinge). The part-frame grasps are kept per
part id and mesh path and moved to the world with each episode's `SceneFacts`, so pose
randomization is handled.
"""

from __future__ import annotations

import logging
from dataclasses import fields
from pathlib import Path

import numpy as np

from realikea.assets.catalog import Catalog
from realikea.errors import RealIkeaError
from realikea.policies.grasp_files import load_grasp_file
from realikea.policies.grasp_sampling import (
    Grasp,
    SamplerParams,
    reachable_pitch,
    reference_rotation,
    sample_grasps,
    world_pitch,
)
from realikea.policies.scripted import (
    OPEN,
    ActionScales,
    Pull,
    Waypoint,
    WaypointPolicy,
    pull_waypoints,
)
from realikea.sim.ik import tcp_rotation
from realikea.tasks.facts import SceneFacts

log = logging.getLogger(__name__)


class GraspSampler(WaypointPolicy):
    """Execute the best sampled (or file-given) antipodal grasp, then pull linearly."""

    name = "grasp_sampler"

    def __init__(
        self,
        scales: ActionScales | None = None,
        params: SamplerParams | None = None,
        grasps: str | Path | None = None,
    ):
        super().__init__(scales if scales is not None else ActionScales())
        self.params = params if params is not None else SamplerParams()
        self._warned: set[str] = set()
        self.grasp_file = Path(grasps) if grasps is not None else None
        self.file_grasps = None
        if self.grasp_file is not None:
            self.file_grasps = load_grasp_file(self.grasp_file, set(Catalog.load().parts))
        self.last_grasp: Grasp | None = None  # the grasp of the latest plan
        self.sampled: dict[tuple, list[Grasp]] = {}  # part-frame grasps per part, mesh, settings

    @classmethod
    def from_config(cls, cfg):
        """The task's action scales and pitch range, and the `cfg.policy` settings."""
        action = cfg.task.action
        scales = ActionScales(float(action.translation_scale), float(action.pitch_scale))
        policy = cfg.get("policy") or {}
        values = {}
        for f in fields(SamplerParams):
            value = policy.get(f.name)
            if value is not None:
                values[f.name] = tuple(value) if f.name == "depth_offsets" else value
        if "max_pitch" not in values:
            low, high = (float(x) for x in cfg.task.workspace.pitch)
            values["max_pitch"] = min(abs(low), abs(high))
        return cls(scales, SamplerParams(**values), policy.get("grasps"))

    def grasps(self, facts: SceneFacts) -> list[Grasp]:
        """The part-frame grasps of the episode's part, best first (cached per part)."""
        reference = reference_rotation(facts)
        if self.file_grasps is not None:
            return self._file_grasps(facts, reference)
        p = self.params
        mu = float(facts.pad_friction if p.friction is None else p.friction)
        key = (facts.part_id, str(facts.visual_mesh), p, mu, float(facts.max_aperture))
        key += (tuple(np.round(reference, 6).ravel()),)
        if key not in self.sampled:
            self.sampled[key] = sample_grasps(
                facts.visual_mesh, reference, mu, facts.max_aperture, p
            )
            if not self.sampled[key]:
                log.warning("grasp_sampler: no grasp found on part %s", facts.part_id)
        return self.sampled[key]

    def _file_grasps(self, facts: SceneFacts, reference: np.ndarray) -> list[Grasp]:
        table = self.file_grasps
        key = facts.part_id if facts.part_id in table else None
        if key not in table:
            raise RealIkeaError(
                f"grasp file {self.grasp_file}: no grasps for part {facts.part_id!r}"
            )
        p = self.params
        for k, pose in enumerate(table[key]):
            if reachable_pitch(pose[:3, :3], reference, p.max_pitch, p.reach_tolerance) is None:
                raise RealIkeaError(
                    f"grasp file {self.grasp_file}: grasp {k} of part {facts.part_id!r} has a "
                    f"rotation the hand cannot reach with its fixed roll and yaw (the jaw axis "
                    f"must be the TCP y axis at a pitch within +-{p.max_pitch} rad)"
                )
        return [Grasp(pose.copy()) for pose in table[key]]

    def plan(self, facts: SceneFacts) -> list[Waypoint]:
        p = self.params
        for grasp in self.grasps(facts):
            rotation = facts.part_rot @ grasp.pose[:3, :3]
            pitch = world_pitch(rotation, facts.tcp_nominal)
            if abs(pitch) > p.max_pitch + 1e-9:
                continue
            position = facts.to_world(grasp.pose[:3, 3])
            approach = tcp_rotation(pitch, facts.tcp_nominal)[:, 2]
            self.last_grasp = grasp
            return [
                Waypoint(position - p.pregrasp * approach, pitch, OPEN, tolerance=0.01),
                Waypoint(position, pitch, OPEN, tolerance=0.004, hold=1, timeout=30),
                *pull_waypoints(
                    position, pitch, facts, Pull(p.pull_distance, p.pull_angle, p.pull_wrist)
                ),
            ]
        self.last_grasp = None
        if facts.config_id not in self._warned:  # once per configuration, not per episode
            self._warned.add(facts.config_id)
            log.warning("grasp_sampler: no reachable grasp for %s; holding still", facts.config_id)
        here = facts.handle_pos + 0.15 * facts.part_rot[:, 2]
        return [Waypoint(here, 0.0, OPEN, tolerance=0.0, timeout=10**9)]
