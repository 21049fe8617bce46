"""A Franka-Panda-class arm with a Franka Hand, authored as MJCF from published data.

Kinematics: the Panda's modified Denavit-Hartenberg table (Franka's published robot data, the
Franka Control Interface documentation). Each link frame is the Craig frame i, so body i sits at
Rx(alpha) Tx(a) Tz(d) in its parent and turns about its own z. Dynamics: link masses, centres of
mass and inertias from the feasible parameter set identified by Gaz et al., "Dynamic identification
of the Franka Emika Panda robot with retrieval of feasible parameters using penalty-based
optimization", IEEE RA-L 4(4), 2019 (the same numbers MuJoCo Menagerie's panda.xml uses); the
hand's 0.73 kg is Franka's datasheet mass.
Torque limits 87/12 Nm are Franka's. Collision: capsules per link and boxes for the hand and
fingers, sized to the real robot's envelope, so contacts stay cheap primitive pairs.

Looks: the Panda's own meshes (pybullet_data's `franka_panda/meshes/`, Apache-2.0, see
realikea/sim/panda_visuals.py) drawn on each link, the hand and both fingers as visual-only
geoms (group 2, no contact, no mass; every body keeps its explicit inertial); the collision
primitives are then in group 3, which MuJoCo does not draw by default. `robot_xml(...,
visuals=False)` leaves the meshes out (and draws the primitives): the same dynamics.

The hand sits at the flange (d = 0.107) turned -45 deg about z as on the real robot. Its two
fingers slide 0-0.04 m each, are coupled by the fixed tendon `split` (half of each finger's
opening) and a joint equality, and one actuator `gripper` drives the tendon. Two drives
(`GripperModel`): the real hand's force-limited drive, and MuJoCo Menagerie's position servo.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

import numpy as np
from omegaconf import DictConfig

from realikea.errors import RealIkeaError
from realikea.sim.panda_visuals import Piece, panda_pieces

# Modified DH (Craig): a_{i-1}, d_i, alpha_{i-1}, lower, upper (m, rad). Row 8 is the flange.
DH_TABLE = (
    (0.0, 0.333, 0.0, -2.8973, 2.8973),
    (0.0, 0.0, -math.pi / 2, -1.7628, 1.7628),
    (0.0, 0.316, math.pi / 2, -2.8973, 2.8973),
    (0.0825, 0.0, math.pi / 2, -3.0718, -0.0698),
    (-0.0825, 0.384, -math.pi / 2, -2.8973, 2.8973),
    (0.0, 0.0, math.pi / 2, -0.0175, 3.7525),
    (0.088, 0.0, math.pi / 2, -2.8973, 2.8973),
)
FLANGE_D = 0.107
HAND_YAW = -math.pi / 4  # the hand is mounted turned -45 deg about the flange z axis

ARM_JOINTS = tuple(f"joint{i}" for i in range(1, 8))
ARM_ACTUATORS = tuple(f"actuator{i}" for i in range(1, 8))
FINGER_JOINTS = ("finger_joint1", "finger_joint2")
GRIPPER_TENDON = "split"
GRIPPER_ACTUATOR = "gripper"
TCP_SITE = "tcp"
HAND_BODY = "hand"
FINGER_BODIES = ("left_finger", "right_finger")
PAD_GEOMS = ("left_pad", "right_pad")

# Franka's joint torque limits (Nm). Position actuators: stiffness (Nm/rad) of the order of Franka's
# joint impedance defaults (MuJoCo Menagerie uses the same), damping (Nm s/rad) about critical for
# the joint-space inertia at the home posture, so a 1 cm TCP step settles in about 0.1 s.
TORQUE_LIMIT = (87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0)
ARM_KP = (4500.0, 4500.0, 3500.0, 3500.0, 2000.0, 2000.0, 2000.0)
ARM_KV = (150.0, 200.0, 150.0, 125.0, 35.0, 35.0, 30.0)
# Time constant (s) of a first-order filter on the joint position commands: the real robot only
# accepts smooth command trajectories (its motion generator interpolates), and an unfiltered 1 cm
# step per control period accelerates a 5.6 kg drawer front hard enough (about 150 N at the pads)
# to break a 70 N pinch at every step.
ARM_COMMAND_FILTER = 0.03
ARM_ARMATURE = 0.1  # kg m^2 reflected rotor inertia per joint
ARM_DAMPING = 1.0  # Nm s/rad viscous joint friction

# Gaz et al. 2019 feasible parameters: mass (kg), CoM (m, link frame), inertia about the CoM
# (Ixx Iyy Izz Ixy Ixz Iyz, kg m^2).
LINK_INERTIA = (
    (4.970684, (0.003875, 0.002081, -0.04762),
     (0.70337, 0.70661, 0.009117, -1.39e-4, 6.772e-3, 0.019169)),
    (0.646926, (-0.003141, -0.02872, 0.003495),
     (7.962e-3, 2.811e-2, 2.5995e-2, -3.925e-3, 1.0254e-2, 7.04e-4)),
    (3.228604, (2.7518e-2, 3.9252e-2, -6.6502e-2),
     (3.7242e-2, 3.6155e-2, 1.083e-2, -4.761e-3, -1.1396e-2, -1.2805e-2)),
    (3.587895, (-5.317e-2, 1.04419e-1, 2.7454e-2),
     (2.5853e-2, 1.9552e-2, 2.8323e-2, 7.796e-3, -1.332e-3, 8.641e-3)),
    (1.225946, (-1.1953e-2, 4.1065e-2, -3.8437e-2),
     (3.5549e-2, 2.9474e-2, 8.627e-3, -2.117e-3, -4.037e-3, 2.29e-4)),
    (1.666555, (6.0149e-2, -1.4117e-2, -1.0517e-2),
     (1.964e-3, 4.354e-3, 5.433e-3, 1.09e-4, -1.158e-3, 3.41e-4)),
    (0.735522, (1.0517e-2, -4.252e-3, 6.1597e-2),
     (1.2516e-2, 1.0027e-2, 4.815e-3, -4.28e-4, -1.196e-3, -7.41e-4)),
)  # fmt: skip
BASE_MASS = 0.629769  # link0 (static)

# Collision capsules per link in the link's own DH frame: (from, to, radius), m. Fitted to the
# Panda's housings: the shoulder and elbow motors sit across their joint axes, the forearm has
# a thick lower part and a slimmer offset upper part, the wrist head carries joint 7's motor.
LINK_CAPSULES = (
    (((0, 0, -0.19), (0, 0, -0.03), 0.06), ((0, -0.065, 0), (0, 0, 0), 0.06)),
    (((0, 0, 0), (0, 0, 0.065), 0.06), ((0, -0.03, 0), (0, -0.2, 0), 0.06)),
    (((0, 0, -0.145), (0, 0, -0.02), 0.06), ((0.0825, 0, 0), (0.0825, 0.07, 0), 0.055)),
    (((0, 0, 0), (0, 0, 0.065), 0.055), ((-0.01, 0.02, 0), (-0.0825, 0.1, 0), 0.055)),
    (((0, 0, -0.27), (0, 0, -0.16), 0.06), ((0, 0.06, -0.17), (0, 0.08, 0), 0.045)),
    (((0, 0, 0), (0.088, 0, 0), 0.05), ((0.088, 0, 0), (0.088, 0.045, 0), 0.045)),
    (((0, 0, 0), (0, 0, 0.062), 0.045),),
)

# Franka Hand (hand frame: z along the approach, y along the finger motion). The housing is about
# 0.06 x 0.2 x 0.066 m; fingers are mounted 0.0584 m below the flange; the default TCP of the
# real hand is 0.1034 m from the flange, at the centre of the fingertip pads.
HAND_MASS = 0.69  # + two fingers = the hand's 0.73 kg
HAND_BOX = ((0.0, 0.0, 0.033), (0.03, 0.1, 0.033))  # centre, half-extents
FINGER_MOUNT_Z = 0.0584
TCP_Z = 0.1034
# One finger in its own frame (origin at the mount, y away from the other finger, the inner
# contact plane at y = 0 when closed). Fingertip: the rubber pad, 18 mm wide (x), 9 mm thick (y),
# 18 mm long (z), ending 54 mm below the mount (0.1124 m below the flange) and centred on the TCP.
# Above it the finger body widens to 14 mm and steps back 8 mm from the contact plane, as the
# real finger's inner face recedes above the pad.
PAD_HALF = (0.009, 0.0045, 0.009)
PAD_THICKNESS = 2 * PAD_HALF[1]  # m across the jaw gap: what a channel must admit
PAD_CENTRE = (0.0, 0.0045, TCP_Z - FINGER_MOUNT_Z)
FINGER_BODY_HALF = (0.009, 0.007, 0.018)
FINGER_BODY_CENTRE = (0.0, 0.015, 0.018)
# Pad contacts: a stiffer-than-default contact (time constant 2 timesteps) so a 70 N squeeze
# presses the pad in by about a millimetre, not several.
PAD_SOLREF = (0.004, 1.0)
PAD_SOLIMP = (0.95, 0.99, 0.001, 0.5, 2.0)
HOUSING_FRICTION = 0.5  # painted aluminium / plastic housing
# geom groups: MuJoCo draws groups 0-2 by default. With the meshes the primitives are hidden.
VISUAL_GROUP, SOLID_GROUP, COLLISION_GROUP = 2, 1, 3


@dataclass(frozen=True)
class GripperModel:
    """The finger drive: one `general` actuator on the tendon `split` plus the finger joints.

    Actuator force on the tendon: gain * ctrl - kp * L - kv * dL/dt, clamped to +-force_limit,
    where L = (q1 + q2) / 2 is the mean finger opening; each finger joint receives half of it,
    so the squeeze force of each jaw on a held object is force_limit / 2 once it saturates.
    """

    name: str
    stroke: float  # m per finger
    ctrl_range: tuple[float, float]
    kp: float  # N/m on the tendon
    kv: float  # N s/m on the tendon
    force_limit: float  # N on the tendon
    finger_damping: float  # N s/m per finger joint
    finger_armature: float  # kg per finger joint
    finger_mass: float  # kg
    pad_friction: float  # sliding friction coefficient of the fingertip pads
    pad_torsion: float  # m, torsional friction of the pads (condim 4)

    @property
    def gain(self) -> float:
        """Actuator gain: a command equal to the top of ctrl_range targets the full stroke."""
        return self.kp * self.stroke / self.ctrl_range[1]

    @property
    def jaw_force_limit(self) -> float:
        """The largest squeeze force (N) each jaw can apply on a held object."""
        return self.force_limit / 2

    def ctrl(self, a):
        """Map a normalized command in [-1, 1] (-1 close, +1 open) affinely to the ctrl range."""
        lo, hi = self.ctrl_range
        a = np.minimum(np.maximum(a, -1.0), 1.0)  # np.clip, without its overhead on a scalar
        return lo + (a + 1.0) * 0.5 * (hi - lo)

    @classmethod
    def from_config(cls, cfg: DictConfig) -> GripperModel:
        """Build from a `realikea/conf/gripper/*.yaml` group: drive `force_limited` or `servo`."""
        common = dict(
            name=str(cfg.name),
            stroke=float(cfg.stroke),
            ctrl_range=(float(cfg.ctrl_range[0]), float(cfg.ctrl_range[1])),
            finger_armature=float(cfg.finger_armature),
            finger_mass=float(cfg.finger_mass),
            pad_friction=float(cfg.pad_friction),
            pad_torsion=float(cfg.pad_torsion),
        )
        if cfg.ctrl_range[0] != 0:
            raise RealIkeaError(f"gripper {cfg.name}: ctrl_range must start at 0 (fully closed)")
        if cfg.drive == "force_limited":
            force = float(cfg.grasp_force)
            return cls(
                **common,
                kp=2 * force / float(cfg.saturation),
                kv=0.0,
                force_limit=2 * force,
                finger_damping=force / float(cfg.finger_speed),
            )
        if cfg.drive == "servo":
            return cls(
                **common,
                kp=float(cfg.kp),
                kv=float(cfg.kv),
                force_limit=float(cfg.force_limit),
                finger_damping=float(cfg.finger_damping),
            )
        raise RealIkeaError(
            f"gripper {cfg.name}: unknown drive {cfg.drive!r} (force_limited|servo)"
        )


def gripper_ctrl(a, gripper: GripperModel):
    """The actuator command for a normalized gripper action a in [-1, 1] (-1 close, +1 open)."""
    return gripper.ctrl(a)


def dh_transform(a: float, d: float, alpha: float, theta: float) -> np.ndarray:
    """Craig's modified DH link transform Rx(alpha) Tx(a) Rz(theta) Tz(d) as a 4x4 matrix."""
    ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array(
        [
            [ct, -st, 0.0, a],
            [st * ca, ct * ca, -sa, -d * sa],
            [st * sa, ct * sa, ca, d * ca],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def dh_flange_pose(q) -> np.ndarray:
    """Flange pose in the robot base frame from the DH table (4x4), independent of MuJoCo."""
    pose = np.eye(4)
    for (a, d, alpha, _, _), theta in zip(DH_TABLE, q, strict=True):
        pose = pose @ dh_transform(a, d, alpha, theta)
    return pose @ dh_transform(0.0, FLANGE_D, 0.0, 0.0)


def joint_limits() -> np.ndarray:
    """(7, 2) lower and upper limits of the arm joints (rad)."""
    return np.array([(lo, hi) for *_, lo, hi in DH_TABLE])


def _f(values) -> str:
    return " ".join(f"{float(v):.9g}" for v in values)


def _quat_x(angle: float) -> tuple[float, ...]:
    return (math.cos(angle / 2), math.sin(angle / 2), 0.0, 0.0)


def _box_inertia(mass: float, half) -> tuple[float, float, float]:
    x, y, z = (2 * h for h in half)
    return (mass * (y * y + z * z) / 12, mass * (x * x + z * z) / 12, mass * (x * x + y * y) / 12)


def _visual_xml(pieces: tuple[Piece, ...], prefix: str) -> str:
    """Visual-only mesh geoms (class `visual`) at the body's origin, one per coloured piece."""
    return "".join(
        f'<geom name="{prefix}_visual{k}" class="visual" mesh="panda_{p.name}" '
        f'rgba="{_f(p.rgba)}"/>'
        for k, p in enumerate(pieces)
    )


def _finger_xml(
    name: str, joint: str, pad: str, gripper: GripperModel, flipped: bool, visuals: bool
) -> str:
    quat = ' quat="0 0 0 1"' if flipped else ""
    # the URDF's right finger is its left one turned half a turn about z, as this body is
    mesh = _visual_xml(panda_pieces()["finger"], name) if visuals else ""
    inertia = _box_inertia(gripper.finger_mass, (0.009, 0.011, 0.027))
    return f"""
      <body name="{name}" pos="0 0 {FINGER_MOUNT_Z}"{quat}>
        <inertial pos="0 0.01 0.027" mass="{gripper.finger_mass}" diaginertia="{_f(inertia)}"/>
        <joint name="{joint}" type="slide" axis="0 1 0" range="0 {gripper.stroke}"
               damping="{gripper.finger_damping:.9g}" armature="{gripper.finger_armature:.9g}"/>
        <geom name="{name}_body" class="housing" type="box" size="{_f(FINGER_BODY_HALF)}"
              pos="{_f(FINGER_BODY_CENTRE)}"/>
        <geom name="{pad}" class="pad" type="box" size="{_f(PAD_HALF)}" pos="{_f(PAD_CENTRE)}"/>
        {mesh}
      </body>"""


def _hand_xml(gripper: GripperModel, pos, quat, fingers: bool = True, visuals: bool = True) -> str:
    centre, half = HAND_BOX
    inertia = _box_inertia(HAND_MASS, half)
    finger_bodies = (
        _finger_xml(FINGER_BODIES[0], FINGER_JOINTS[0], PAD_GEOMS[0], gripper, False, visuals)
        + _finger_xml(FINGER_BODIES[1], FINGER_JOINTS[1], PAD_GEOMS[1], gripper, True, visuals)
        if fingers
        else ""
    )
    mesh = _visual_xml(panda_pieces()[HAND_BODY], HAND_BODY) if visuals else ""
    return f"""
    <body name="{HAND_BODY}" pos="{_f(pos)}" quat="{_f(quat)}" gravcomp="1">
      <inertial pos="{_f(centre)}" mass="{HAND_MASS}" diaginertia="{_f(inertia)}"/>
      <geom name="hand_housing" class="housing" type="box" size="{_f(half)}" pos="{_f(centre)}"/>
      <site name="{TCP_SITE}" pos="0 0 {TCP_Z}" size="0.004" rgba="1 0.2 0.2 1" group="4"/>
      {mesh}{finger_bodies}
    </body>"""


def _arm_xml(hand: str, visuals: bool = True) -> str:
    """link0 .. link7 nested from the DH table, the hand at the flange; each link's mesh in its
    body's frame (the URDF's link frame i is the Craig frame i this table gives body i)."""
    pieces = panda_pieces() if visuals else {}
    inner = hand
    for i in range(7, 0, -1):
        a, d, alpha, lo, hi = DH_TABLE[i - 1]
        mass, com, inertia = LINK_INERTIA[i - 1]
        tau = TORQUE_LIMIT[i - 1]
        pos = (a, -math.sin(alpha) * d, math.cos(alpha) * d)
        geoms = "".join(
            f'<geom name="link{i}_c{k}" class="link" type="capsule" size="{r}" '
            f'fromto="{_f(p0)} {_f(p1)}"/>'
            for k, (p0, p1, r) in enumerate(LINK_CAPSULES[i - 1])
        )
        geoms += _visual_xml(pieces.get(f"link{i}", ()), f"link{i}")
        inner = f"""
  <body name="link{i}" pos="{_f(pos)}" quat="{_f(_quat_x(alpha))}" gravcomp="1">
    <inertial pos="{_f(com)}" mass="{mass}" fullinertia="{_f(inertia)}"/>
    <joint name="joint{i}" range="{lo} {hi}" actuatorfrcrange="{-tau} {tau}"/>
    {geoms}{inner}
  </body>"""
    return f"""
<body name="link0">
  <inertial pos="-0.041 0 0.05" mass="{BASE_MASS}" diaginertia="0.00315 0.00388 0.004285"/>
  <geom name="link0_c0" class="link" type="cylinder" size="0.09 0.07" pos="-0.03 0 0.07"/>
  {_visual_xml(pieces.get("link0", ()), "link0")}{inner}
</body>"""


def _arm_actuators(command_filter: float) -> str:
    """The arm's position actuators; `command_filter` > 0 filters their commands (s)."""
    dynamics = f'dyntype="filterexact" dynprm="{command_filter:g}"' if command_filter > 0 else ""
    return "".join(
        f'<general name="{act}" joint="{jnt}" ctrlrange="{lo} {hi}" '
        f'forcerange="{-tau} {tau}" gainprm="{kp}" biasprm="0 {-kp} {-kv}" {dynamics}/>'
        for act, jnt, (*_, lo, hi), tau, kp, kv in zip(
            ARM_ACTUATORS, ARM_JOINTS, DH_TABLE, TORQUE_LIMIT, ARM_KP, ARM_KV, strict=True
        )
    )


def _finger_drive_xml(gripper: GripperModel) -> tuple[str, str]:
    """The fingers' actuator, and their tendon and equality coupling."""
    lim = gripper.force_limit
    actuator = f"""
    <general name="{GRIPPER_ACTUATOR}" tendon="{GRIPPER_TENDON}"
             ctrlrange="{_f(gripper.ctrl_range)}" forcerange="{-lim} {lim}"
             gainprm="{gripper.gain:.9g}" biasprm="0 {-gripper.kp:.9g} {-gripper.kv:.9g}"/>"""
    coupling = f"""
  <tendon>
    <fixed name="{GRIPPER_TENDON}">
      <joint joint="{FINGER_JOINTS[0]}" coef="0.5"/>
      <joint joint="{FINGER_JOINTS[1]}" coef="0.5"/>
    </fixed>
  </tendon>
  <equality>
    <joint joint1="{FINGER_JOINTS[0]}" joint2="{FINGER_JOINTS[1]}" solref="0.005 1"
           solimp="0.95 0.99 0.001"/>
  </equality>"""
    return actuator, coupling


def _panda_assets(arm: bool, fingers: bool) -> str:
    """The Panda's visual meshes of the bodies built."""
    # the Panda's meshes from the installed pybullet_data (Apache License 2.0, the file
    # pybullet_data/franka_panda/LICENSE.txt; copyright Franka Robotics GmbH, formerly
    # Franka Emika GmbH, per franka_ros's NOTICE), split by colour into the cache; absolute
    # paths, so no meshdir touches the meshes of a configuration attached to this model
    used = {"link0", "link1", "link2", "link3", "link4", "link5", "link6", "link7"}
    used = (used if arm else set()) | {HAND_BODY} | ({"finger"} if fingers else set())
    meshes = "".join(
        f'\n    <mesh name="panda_{p.name}" file={quoteattr(str(p.file))} inertia="shell"/>'
        for body, pieces in panda_pieces().items() if body in used for p in pieces
    )  # fmt: skip
    return f"\n  <asset>{meshes}\n  </asset>"


def robot_xml(
    gripper: GripperModel,
    arm: bool = True,
    fingers: bool = True,
    hand_pos=(0.0, 0.0, 0.5),
    command_filter: float = ARM_COMMAND_FILTER,
    visuals: bool = True,
) -> str:
    """The robot as a standalone MJCF document.

    With `arm=False` only the hand is built, fixed in the world at `hand_pos` with its approach
    axis pointing down the world z axis (gripper tests). With `fingers=False` the fingers, their
    tendon, equality and actuator are left out (a kinematic model for IK). `command_filter` is
    the time constant (s) of the arm actuators' command filter; 0 applies commands at once.
    `visuals` draws the Panda's meshes (visual only) and hides the collision primitives;
    without them the primitives are drawn. Either way the same collision, masses and dynamics.
    """
    if arm:
        yaw = (math.cos(HAND_YAW / 2), 0.0, 0.0, math.sin(HAND_YAW / 2))
        body = _arm_xml(_hand_xml(gripper, (0.0, 0.0, FLANGE_D), yaw, fingers, visuals), visuals)
        actuators = _arm_actuators(command_filter)
    else:
        body = _hand_xml(gripper, hand_pos, (0.0, 1.0, 0.0, 0.0), fingers, visuals)
        actuators = ""
    coupling = ""
    if fingers:
        finger_actuator, coupling = _finger_drive_xml(gripper)
        actuators += finger_actuator
    group = COLLISION_GROUP if visuals else SOLID_GROUP
    assets = _panda_assets(arm, fingers) if visuals else ""
    return f"""<mujoco model="panda_{gripper.name}">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="0.002" integrator="implicitfast"/>
  <default>
    <joint armature="{ARM_ARMATURE}" damping="{ARM_DAMPING}" actuatorgravcomp="true"/>
    <general dyntype="none" biastype="affine"/>
    <default class="link">
      <geom contype="2" conaffinity="1" group="{group}" friction="{HOUSING_FRICTION} 0.005 0.0001"
            rgba="0.92 0.93 0.93 1"/>
    </default>
    <default class="housing">
      <geom contype="2" conaffinity="1" group="{group}" friction="{HOUSING_FRICTION} 0.005 0.0001"
            rgba="0.25 0.25 0.25 1"/>
    </default>
    <default class="pad">
      <geom contype="2" conaffinity="1" group="{group}" condim="4" rgba="0.1 0.1 0.1 1"
            friction="{gripper.pad_friction} {gripper.pad_torsion} 0.0001"
            solref="{_f(PAD_SOLREF)}" solimp="{_f(PAD_SOLIMP)}"/>
    </default>
    <default class="visual">
      <geom type="mesh" contype="0" conaffinity="0" group="{VISUAL_GROUP}" mass="0"/>
    </default>
  </default>{assets}
  <worldbody>
    {body}
  </worldbody>{coupling}
  <actuator>{actuators}
  </actuator>
</mujoco>
"""
