"""The paper's friction-based "normal way": a fixed-orientation parallel-jaw grasp, then a pull."""

from __future__ import annotations

from realikea.policies.scripted import OPEN, Waypoint, WaypointPolicy, pull_waypoints
from realikea.tasks.facts import SceneFacts

PREGRASP = 0.08  # m in front of the handle along the front's normal


class HeuristicPull(WaypointPolicy):
    """Jaws open in front of the handle point, advance onto it, close, pull straight back."""

    name = "heuristic_pull"

    def plan(self, facts: SceneFacts) -> list[Waypoint]:
        normal = facts.part_rot[:, 2]  # out of the front
        grasp = facts.handle_pos
        return [
            Waypoint(grasp + PREGRASP * normal, 0.0, OPEN, tolerance=0.01),
            Waypoint(grasp, 0.0, OPEN, tolerance=0.004, hold=1, timeout=30),
            *pull_waypoints(grasp, 0.0, facts),
        ]
