"""Step 5, assembly and joint parameterization: carcass, moving front, mounted part, joint.

Cabinet frame: origin at the bottom centre of the carcass's front plane, +x out of the front
(towards the robot), +y to the viewer's right, +z up. The carcass and the moving front are
sibling bodies so their contacts are simulated; the drawer tray is an internal feature and
only visual (step 2 for bases).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

from realikea.assets.catalog import Base, Part
from realikea.assets.workflow.clipping import inset_half_extents
from realikea.sim.resistance import handle_resistance, lever_arm

PANEL = 0.018  # m carcass board thickness
TRAY_BOARD = 0.012  # m drawer tray board thickness
GRASP_DEPTH = 0.006  # m below the part's top surface where the handle site sits
FRONT_GAP = 0.001  # m between the closed front's back face and the carcass edge
BOARD_DENSITY = 650.0  # kg/m^3 particle board
PART_DENSITY = {  # kg/m^3 by friction class: zinc die-cast, plastic, wood, coated metal
    "polished_metal": 6600.0,
    "brushed_metal": 6600.0,
    "plastic": 1200.0,
    "wood": 700.0,
    "rubberized": 6600.0,
}
SOLID_GROUP, VISUAL_GROUP, COLLISION_GROUP = 1, 2, 3  # seen and colliding; seen; colliding
WOOD_RGBA = (0.82, 0.74, 0.62, 1.0)
PART_RGBA = (0.55, 0.57, 0.6, 1.0)
COLLISION_RGBA = (0.9, 0.3, 0.2, 0.5)
# Joint dry friction: MuJoCo's friction loss is a soft constraint that lets a joint creep under
# a load below its friction level; a stiff reference and high impedance keep that creep under
# 0.2 mm/s at 75 % of the friction level (tests/test_physics.py), i.e. static friction.
FRICTION_SOLREF = (0.01, 1.0)
FRICTION_SOLIMP = (0.99, 0.999, 0.001)


@dataclass(frozen=True)
class Geom:
    """One MuJoCo geom: a box (half-extents) or a mesh asset, visual-only or colliding."""

    name: str
    pos: tuple[float, ...] = (0.0, 0.0, 0.0)
    quat: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)
    box: tuple[float, ...] | None = None
    mesh: str | None = None
    collides: bool = True
    density: float = 0.0
    friction: float = 1.0
    rgba: tuple[float, ...] = WOOD_RGBA
    group: int = COLLISION_GROUP  # for colliding geoms: SOLID_GROUP if it is also the visual


@dataclass(frozen=True)
class Joint:
    """The front's one degree of freedom with its resistance, anchor and axis in its body's frame:
    what the workflow writes into the MJCF and what the exporters read back from it."""

    name: str
    type: str  # slide | hinge
    pos: tuple[float, ...]
    axis: tuple[float, ...]
    range: tuple[float, float]
    damping: float
    frictionloss: float


@dataclass(frozen=True)
class Site:
    """A named point (and frame) on a body, e.g. the handle's grasp point."""

    name: str
    pos: tuple[float, ...]
    quat: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Body:
    name: str
    geoms: list[Geom]
    joint: Joint | None = None
    pos: tuple[float, ...] = (0.0, 0.0, 0.0)
    sites: list[Site] = field(default_factory=list)
    quat: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)
    children: list[Body] = field(default_factory=list)  # welded to this body (no joint)


@dataclass(frozen=True)
class Assembly:
    """A configuration ready to serialise: bodies under one root and the mesh files they use."""

    name: str
    bodies: list[Body]
    meshes: dict[str, str] = field(default_factory=dict)  # asset name -> relative file


def carcass(base: Base) -> Body:
    """The static cabinet: two sides, top, bottom and back, all colliding boxes."""
    w, h, d, t = base.width / 2, base.height, base.depth, PANEL
    boxes = {
        "side_left": ((-d / 2, -w + t / 2, h / 2), (d / 2, t / 2, h / 2)),
        "side_right": ((-d / 2, w - t / 2, h / 2), (d / 2, t / 2, h / 2)),
        "bottom": ((-d / 2, 0, t / 2), (d / 2, w - t, t / 2)),
        "top": ((-d / 2, 0, h - t / 2), (d / 2, w - t, t / 2)),
        "back": ((-d + t / 2, 0, h / 2), (t / 2, w - t, h / 2 - t)),
    }
    geoms = [
        Geom(f"carcass_{k}", pos, box=half, group=SOLID_GROUP) for k, (pos, half) in boxes.items()
    ]
    return Body("carcass", geoms)


def front_outline(base: Base) -> tuple[np.ndarray, np.ndarray]:
    """Centre and half-extents of the closed front's visual box."""
    half = np.array(
        [base.front_thickness / 2, base.width / 2 - base.reveal, base.height / 2 - base.reveal]
    )
    centre = np.array([FRONT_GAP + base.front_thickness / 2, 0.0, base.height / 2])
    return centre, half


def mount_pose(base: Base) -> tuple[np.ndarray, np.ndarray]:
    """Position and quaternion (w, x, y, z) of the part frame on the front's outer face."""
    centre, half = front_outline(base)
    pos = centre + np.array(
        [half[0], (2 * base.mount_u - 1) * half[1], (2 * base.mount_v - 1) * half[2]]
    )
    to_front = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # part x,y,z columns
    rot = Rotation.from_matrix(to_front) * Rotation.from_euler(
        "z", base.mount_roll_deg, degrees=True
    )
    x, y, z, w = rot.as_quat()
    return pos, np.array([w, x, y, z])


def front_joint(base: Base, damping: float, frictionloss: float, handle: np.ndarray) -> Joint:
    """Slide along +x for drawers; for doors and flaps a hinge along the front's outer edge (where
    a concealed hinge's linkage swings it clear of a neighbouring front 3 mm away), its
    resistance scaled to the lever arm of `handle` (front frame) so the handle feels a drawer's."""
    _, half = front_outline(base)
    if base.kind == "drawer":
        return Joint(
            "front_joint", "slide", (0, 0, 0), (1, 0, 0), (0, base.travel), damping, frictionloss
        )
    face = FRONT_GAP + base.front_thickness
    if base.kind == "flap":
        pos, axis = (face, 0, base.reveal), (0, 1, 0)
    else:
        side = -1 if base.hinge == "left" else 1
        pos, axis = (face, side * half[1], 0), (0, 0, side)
    damping, frictionloss = handle_resistance(
        "hinge", lever_arm(pos, axis, handle), damping, frictionloss
    )
    return Joint("front_joint", "hinge", pos, axis, (0, base.travel), damping, frictionloss)


def drawer_tray(base: Base) -> list[Geom]:
    """The box behind a drawer front: visual only, it never touches the carcass (step 2)."""
    t = TRAY_BOARD
    depth = min(base.travel + 0.05, base.depth - PANEL - 0.01)
    half_w = base.width / 2 - PANEL - 0.013
    h = max(base.height - 2 * base.reveal - 0.04, 0.04)
    z0 = base.reveal + 0.01
    x_mid = FRONT_GAP - depth / 2
    boxes = {
        "tray_bottom": ((x_mid, 0, z0 + t / 2), (depth / 2, half_w, t / 2)),
        "tray_left": ((x_mid, -half_w + t / 2, z0 + h / 2), (depth / 2, t / 2, h / 2)),
        "tray_right": ((x_mid, half_w - t / 2, z0 + h / 2), (depth / 2, t / 2, h / 2)),
        "tray_back": ((FRONT_GAP - depth + t / 2, 0, z0 + h / 2), (t / 2, half_w, h / 2)),
    }
    return [
        Geom(k, pos, box=half, collides=False, density=BOARD_DENSITY)
        for k, (pos, half) in boxes.items()
    ]


def grasp_point(visual: trimesh.Trimesh) -> np.ndarray:
    """The handle point in the part frame: just below the top surface above the mount point."""
    top = visual.bounds[1][2] + 0.01
    hits, _, _ = visual.ray.intersects_location([[0.0, 0.0, top]], [[0.0, 0.0, -1.0]])
    z_top = float(hits[:, 2].max()) if len(hits) else visual.bounds[1][2]
    return np.array([0.0, 0.0, z_top - min(GRASP_DEPTH, z_top / 2)])


def assemble(
    part: Part,
    base: Base,
    collision_meshes: dict[str, str],
    visual_mesh: str,
    handle: np.ndarray,
    damping: float,
    frictionloss: float,
    front_clearance: float,
) -> Assembly:
    """Put a part on a base's front with the chosen collision meshes and joint resistance."""
    centre, half = front_outline(base)
    front = [
        Geom("front_visual", tuple(centre), box=tuple(half), collides=False, density=BOARD_DENSITY),
        Geom(
            "front_collision",
            tuple(centre),
            box=tuple(inset_half_extents(half, front_clearance)),
            rgba=COLLISION_RGBA,
        ),
    ]
    pos, quat = mount_pose(base)
    part_geoms = [
        Geom(
            "part_visual",
            mesh="part_visual",
            collides=False,
            density=PART_DENSITY[part.friction],
            rgba=PART_RGBA,
        ),
        *(
            Geom(
                f"part_collision_{i:03d}",
                mesh=name,
                friction=part.friction_coefficient,
                rgba=COLLISION_RGBA,
            )
            for i, name in enumerate(collision_meshes)
        ),
    ]
    # the part is its own body in the part frame, welded to the front: moving it (pose
    # randomization) moves its geoms, their collision bounds and the handle site together
    mounted = Body(
        "part", part_geoms, pos=tuple(pos), quat=tuple(quat), sites=[Site("handle", tuple(handle))]
    )
    trays = drawer_tray(base) if base.kind == "drawer" else []
    mount = Rotation.from_quat(np.roll(quat, -1))  # scipy wants (x, y, z, w)
    joint = front_joint(base, damping, frictionloss, pos + mount.apply(handle))
    moving = Body("front", front + trays, joint, children=[mounted])
    meshes = {"part_visual": visual_mesh, **collision_meshes}
    return Assembly(f"{part.id}__{base.id}", [carcass(base), moving], meshes)
