"""A scripted upper bound that opens by form closure: fingertips behind the handle, not a pinch.

It stands in for the paper's human teleoperation: a person does not squeeze a drawer handle,
they hook a finger behind it. The plan is made from the part's geometry alone (the part frame
of `SceneFacts` and what its visual mesh offers to catch, `catch_geometry`), never tuned per
configuration, so imported parts work like catalog ones. Part frame: z out of the front, x
along the bar or lip, y "up" for a drawer's part (finger-pull lips open towards -y); on doors
the frame and the hand are both rolled, so the same plan holds.

Two ways of catching the part, chosen by its category:

* **loop** (two-point handles): the open jaws straddle the bar (one pad above, one below),
  advance until the pads are in the gap between the bar and the front, and close there. The
  closed pads stick 8 mm out of the finger bodies (`docs/task.md`, "Franka Hand"), so the jaws close
  around the bar with the bodies clear of it and the pads' back faces behind it: pulling loads
  the bar with the pads' normal force along the opening direction, whatever the squeeze. A bar
  taller than the bodies' clearance gets a partial closure (the bodies still clear the bar).
* **wedge** (knobs from above, from below where the arm stands under the handle, or from the
  hinge's side on doors; finger-pull lips from below): the hand is pitched so one finger leads;
  that finger's pad slides along its own inner face past the feature's edge (the back rim of a
  knob's head, the inner bottom edge of a lip) into the space behind it, then pulls. The
  inclined inner face pushes the edge out along the opening direction and across it (towards the
  knob's axis, up on a lip), the front's joint and the stiff arm taking the cross component: the
  normal force carries the pull. The other jaw stays wide open, clear of it all. On doors the
  wrist follows a knob's whole turn (`door_pull_wrist`), so the head does not turn off the pad;
  behind a lip it holds its pitch (`lip_door_pull_wrist`): turning with the door, its first step
  tips the pad off the edge. The pull drags the lip's edge along the door's arc, the hand
  keeping its offset to it (`scripted.held_path`): the TCP's own arc is 4 cm off the edge's, and
  the arm fought the door along it until joint 6 stood at its torque limit. On a flap the wrist
  follows half of its turn behind a lip (`lip_flap_pull_wrist`): following 0.3, as for bars and
  knobs, friction carried over half the pull in a fifth of the openings (train parts:
  experiments/kitchen/README.md).

A part with nothing to get behind (a knob without an undercut: cylinders, cones; a bar without
a gap behind it; a pull without a channel) gets no plan: the hand holds still with the gripper
open, and the episode's note says why (`WaypointPolicy.note`, the eval's `policy_notes`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from realikea.assets.catch_geometry import NoCatch, catch_features_at
from realikea.policies.scripted import (
    OPEN,
    ActionScales,
    NoPlan,
    Pull,
    Waypoint,
    WaypointPolicy,
    follow,
    held_path,
)
from realikea.sim.ik import tcp_rotation
from realikea.sim.robot import PAD_THICKNESS
from realikea.tasks.facts import SceneFacts

# fingertip pad (realikea/sim/robot.py): the TCP is the pad centre
PAD_HALF_LENGTH = 0.009  # m along the approach
BODY_STEP = 0.008  # m the finger body steps back from the pad's contact plane


@dataclass(frozen=True)
class OracleParams:
    """Geometric constants of the plan (realikea/conf/policy/hook_oracle.yaml documents them)."""

    clearance: float = 0.002  # m kept between the hand and the part or the front while placing
    standoff: float = 0.04  # m in front of the part where the approach starts
    pull_distance: float = 0.4  # m of the pull along a drawer's opening direction
    pull_angle: float = 1.2  # rad a door or flap is turned along its arc (success: 0.785)
    pull_wrist: float = 0.3  # share of a flap's turn the wrist follows
    door_pull_wrist: float = 1.0  # share of a door's turn the wrist follows
    lip_door_pull_wrist: float = 0.0  # the same for a lip's wedge on a door
    lip_flap_pull_wrist: float = 0.5  # the same for a lip's wedge on a flap
    wedge_pitch: float = 0.55  # rad the hand is tipped towards a knob's head for its wedge
    lip_pitch: float = 0.6  # rad tipped up for a lip's wedge
    wedge_depth: float = 0.008  # m the pad's tip goes past the edge along the approach, at most
    wedge_preload: float = 0.001  # m the pad's face is set into the edge before the pull
    loop_body_clearance: float = 0.002  # m between a closed finger body and the bar


@dataclass(frozen=True)
class Catch:
    """Where the plan puts the hand in the part frame (y, z) and how it holds there."""

    mode: str  # "loop" or "wedge"
    pitch: float
    tcp: np.ndarray  # (3,) part-frame TCP at the catch
    approach: np.ndarray  # (3,) part-frame unit vector the hand slides in along
    away: np.ndarray  # (3,) part-frame unit vector off the part (backing off the face)
    grip: float  # gripper command while catching and pulling
    held: np.ndarray  # (3,) part-frame point the pull drags along the front's path


def _features(facts: SceneFacts) -> dict:
    """The part's catchable geometry (metres, part frame) from its visual mesh; `NoPlan` if it
    offers nothing to get behind."""
    found = catch_features_at(str(facts.visual_mesh), facts.category)
    if isinstance(found, NoCatch):
        raise NoPlan(found.reason)
    return asdict(found)


# m of handle height above the arm's base under which a knob's wedge comes from below: the hand
# tips up 0.55 rad there (+1.6 rad with the handle 0.15 m above the base), not with it 0.80 m
# above (+0.56 at most: experiments/reach/README.md)
LOW_HANDLE = 0.5


def _knob_side(facts: SceneFacts) -> float:
    """The part-frame y side (+1 or -1) a knob's wedge comes from: the hinge's side on doors
    (traced on `knob_mushroom_38`, `door_left_w40_h80`: from the other side the wrist ran joint
    6 into its limit and the door stayed shut); on drawers and flaps from above, or from below
    where the arm stands under the handle (`LOW_HANDLE`): from above, the hand's housing meets
    the worktop over a stack's top drawer (experiments/kitchen/results/hand_contacts.md)."""
    if facts.base_kind == "door":
        return 1.0 if facts.to_part(facts.hinge_anchor)[1] > 0 else -1.0
    return -1.0 if facts.handle_pos[2] - facts.robot_base[2] < LOW_HANDLE else 1.0


class HookOracle(WaypointPolicy):
    """Form closure from the part's geometry: a loop behind bars, a wedge behind knobs and lips."""

    name = "hook_oracle"

    def __init__(self, scales: ActionScales | None = None, params: OracleParams | None = None):
        super().__init__(scales or ActionScales())
        self.params = params or OracleParams()

    @classmethod
    def from_config(cls, cfg):
        action = cfg.task.action
        scales = ActionScales(float(action.translation_scale), float(action.pitch_scale))
        fields = OracleParams.__dataclass_fields__
        params = OracleParams(**{k: float(v) for k, v in cfg.policy.items() if k in fields})
        return cls(scales, params)

    # --- the catch --------------------------------------------------------------------------
    def _axes(self, facts: SceneFacts, pitch: float) -> tuple[np.ndarray, np.ndarray]:
        """Part-frame approach and jaw axes of the TCP at a pitch."""
        rot = facts.part_rot.T @ tcp_rotation(pitch, facts.tcp_nominal)
        return rot[:, 2], rot[:, 1]

    def _aperture_command(self, facts: SceneFacts, aperture: float) -> float:
        return float(np.clip(2.0 * aperture / facts.max_aperture - 1.0, -1.0, 1.0))

    def _loop(self, facts: SceneFacts) -> Catch:
        p, f = self.params, _features(facts)
        approach, _ = self._axes(facts, 0.0)
        gap = f["proj"] - f["depth"]  # between the bar's back and the front
        # the pads wholly in the gap if they fit, else as deep as the front allows
        z = max(PAD_HALF_LENGTH + 0.0005, min(gap / 2, gap - PAD_HALF_LENGTH - p.clearance))
        # closed jaws with the finger bodies clear of the bar; a short bar lets them meet
        aperture = max(0.0, f["height"] + 2 * p.loop_body_clearance - 2 * BODY_STEP)
        tcp = np.array([0.0, 0.0, z])
        grip = self._aperture_command(facts, aperture)
        return Catch("loop", 0.0, tcp, approach, -approach, grip, tcp)

    def _wedge(self, facts: SceneFacts) -> Catch:
        """Lead with one pad whose inner face lies on the feature's edge, tip behind it."""
        p, f = self.params, _features(facts)
        knob = facts.category == "knob"
        side = _knob_side(facts) if knob else 1.0
        # the part-frame y the hand moves along as it slides in: towards a knob's axis from the
        # side it comes from (the jaws straddle the head), up into a lip's channel
        towards = -side if knob else 1.0
        pitch = p.wedge_pitch if knob else p.lip_pitch
        a, j = self._axes(facts, pitch)
        if a[1] * towards < 0:  # a rolled hand (doors) tips the other way for the same pitch
            pitch = -pitch
            a, j = self._axes(facts, pitch)
        sign = 1.0 if j[2] < 0 else -1.0  # the finger that leads (further towards the front)
        normal = -sign * j  # its inner face's normal, towards the other jaw
        if knob:
            edge = np.array([0.0, side * f["radius"], f["back"]])
            # the face must pass outside the neck
            room_y = (f["radius"] - f["neck"] - p.clearance) / max(abs(a[1]), 1e-6)
        else:
            edge = np.array([0.0, f["edge_y"], f["edge_z"]])
            room_y = (f["top"] - edge[1] - p.clearance) / max(abs(a[1]), 1e-6)
        # the pad's outer tip corner must stay clear of the front (or the pull's back plate)
        back = 0.0 if knob else f["back"]
        corner = PAD_THICKNESS * abs(normal[2])
        room_z = (edge[2] - back - p.clearance - corner) / max(abs(a[2]), 1e-6)
        depth = max(0.0, min(p.wedge_depth, room_y, room_z))
        tip = edge + depth * a + p.wedge_preload * normal  # the pad's inner tip edge, set in
        half_gap = facts.max_aperture / 2
        tcp = tip - sign * half_gap * j - PAD_HALF_LENGTH * a
        # a lip's edge is dragged along the front's arc (the hand held level on doors keeps its
        # offset to it); a knob's wedge keeps the TCP's own arc, with which its cells were
        # measured (dragging its edge opened fewer knob flaps: experiments/kitchen/README.md)
        return Catch("wedge", pitch, tcp, a, -normal, OPEN, tcp if knob else edge)

    def catch(self, facts: SceneFacts) -> Catch:
        return self._loop(facts) if facts.category == "two_point" else self._wedge(facts)

    # --- the plan ---------------------------------------------------------------------------
    def plan(self, facts: SceneFacts) -> list[Waypoint]:
        p, c = self.params, self.catch(facts)
        lip = facts.category == "finger_pull"
        wrist = p.lip_flap_pull_wrist if lip else p.pull_wrist
        if facts.base_kind == "door":
            wrist = p.lip_door_pull_wrist if lip else p.door_pull_wrist
        world = facts.to_world
        at = world(c.tcp)
        if c.mode == "loop":
            start = world(c.tcp - p.standoff * c.approach)
            near = world(c.tcp - p.clearance * c.approach)
            steps = [
                Waypoint(start, 0.0, OPEN, tolerance=0.01, timeout=60, name="start"),
                Waypoint(near, 0.0, OPEN, tolerance=0.003, timeout=25, name="near"),
                Waypoint(at, 0.0, OPEN, tolerance=0.002, hold=2, timeout=15, name="catch"),
                Waypoint(at, 0.0, c.grip, tolerance=1.0, hold=9, timeout=10, name="close"),
            ]
        else:
            off = (p.clearance + p.wedge_preload) * c.away
            turn = int(np.ceil(abs(c.pitch) / self.scales.pitch)) + 2  # steps to tip the hand
            start = world(c.tcp - p.standoff * c.approach + off)
            slid = world(c.tcp + off)
            # tipping down works on the way; tipping up only once there (the wrist's joint 5)
            level = 0.0 if c.pitch > 0 else c.pitch
            steps = [
                Waypoint(start, level, OPEN, tolerance=0.01, timeout=60, name="start"),
                Waypoint(start, c.pitch, OPEN, 0.01, hold=turn, timeout=turn + 10, name="tip"),
                Waypoint(slid, c.pitch, OPEN, tolerance=0.003, timeout=25, name="slide"),
                Waypoint(at, c.pitch, OPEN, tolerance=0.002, hold=2, timeout=10, name="catch"),
            ]
        held = world(c.held)
        path = Pull(p.pull_distance, p.pull_angle, wrist).path(held, facts)
        return [*steps, *follow(held_path(path, held, at, facts), c.pitch, c.grip)]
