"""A fitted kitchen around one configuration: neighbouring fronts at real gaps, worktop, plinth.

The configuration's own carcass and front stay as built; the run is added to its root body
(`unit`), so base pose randomization moves the whole run with it. Dimensions come from
`realikea/conf/scene/kitchen.yaml` (sources in docs/task.md, "Kitchen scene"). Every box collides: a
policy can no longer squeeze a front's free edge or hook over its top, because in a kitchen a
neighbouring front or the worktop stands 3 mm away.

Cabinet frame (as built): origin at the bottom centre of the carcass's front plane, +x out of
the front, +y to the viewer's right, +z up; the configuration stands at `elevation` above the
floor. Base units (drawers, doors) stand on the plinth under the worktop; a flap hangs in a
wall unit above the worktop, recessed behind the base run by the difference in depths.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from omegaconf import DictConfig

from realikea.errors import RealIkeaError

CARCASS_RGBA = (0.86, 0.84, 0.80, 1.0)
FRONT_RGBA = (0.93, 0.92, 0.89, 1.0)
WORKTOP_RGBA = (0.42, 0.36, 0.30, 1.0)
PLINTH_RGBA = (0.25, 0.25, 0.25, 1.0)


@dataclass(frozen=True)
class Unit:
    """What the kitchen needs to know of a configuration, read from its MJCF."""

    kind: str  # drawer, door or flap
    width: float  # carcass (m)
    height: float
    depth: float
    front_back: float  # x of the front's back face
    front_face: float  # x of the front's outer face
    reveal: float  # m between the front's edge and the carcass's edge


def read_unit(cabinet: mujoco.MjSpec, kind: str) -> Unit:
    """Carcass and front dimensions from the configuration's geoms."""
    geoms = {n: cabinet.geom(n) for n in ("carcass_bottom", "carcass_side_left", "carcass_top")}
    front = cabinet.geom("front_visual")
    if front is None or any(g is None for g in geoms.values()):
        raise RealIkeaError(f"the configuration lacks one of {[*geoms, 'front_visual']}")
    side, bottom, top = geoms["carcass_side_left"], geoms["carcass_bottom"], geoms["carcass_top"]
    width = 2 * (abs(float(side.pos[1])) + float(side.size[1]))
    height = float(top.pos[2] + top.size[2])
    return Unit(
        kind=kind,
        width=width,
        height=height,
        depth=2 * float(bottom.size[0]),
        front_back=float(front.pos[0] - front.size[0]),
        front_face=float(front.pos[0] + front.size[0]),
        reveal=width / 2 - float(front.size[1]),
    )


def elevation(unit: Unit, kitchen: DictConfig) -> float:
    """Height of the configuration's bottom above the floor in the kitchen (m)."""
    base_top = float(kitchen.plinth_height + kitchen.carcass_height)
    if unit.kind == "flap":
        return base_top + float(kitchen.worktop_thickness + kitchen.wall_unit_above_worktop)
    if unit.kind == "door":
        return float(kitchen.plinth_height)
    fronts, slot = _drawer_stack(unit, kitchen)
    return base_top - sum(fronts[:slot]) - unit.height


def _drawer_stack(unit: Unit, kitchen: DictConfig) -> tuple[list[float], int]:
    """The base unit's fronts (top first) and the slot the configuration's drawer takes."""
    for stack in kitchen.drawer_stacks:
        fronts, slot = [float(f) for f in stack.fronts], int(stack.slot)
        if abs(fronts[slot] - unit.height) < 1e-3:
            if abs(sum(fronts) - float(kitchen.carcass_height)) > 1e-3:
                raise RealIkeaError(f"scene.drawer_stacks {fronts} do not fill the carcass height")
            return fronts, slot
    raise RealIkeaError(
        f"no stack in scene.drawer_stacks has a {unit.height:.2f} m drawer front; add one"
    )


class _Boxes:
    """Adds named colliding boxes to a body from their min / max corners (cabinet frame)."""

    def __init__(self, body: mujoco.MjsBody):
        self.body = body

    def add(self, name: str, lo, hi, rgba) -> None:
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        if np.any(hi - lo <= 0):
            return
        self.body.add_geom(
            name=f"kitchen_{name}", type=mujoco.mjtGeom.mjGEOM_BOX, size=(hi - lo) / 2,
            pos=(hi + lo) / 2, rgba=list(rgba), group=1,
        )  # fmt: skip


def add_kitchen(cabinet: mujoco.MjSpec, unit: Unit, kitchen: DictConfig) -> float:
    """Build the run around the configuration (geoms on its root body); returns its elevation."""
    z0 = elevation(unit, kitchen)
    boxes = _Boxes(cabinet.body("unit"))
    g, r = float(kitchen.front_gap), unit.reveal
    half_w, side_w = unit.width / 2, float(kitchen.neighbour_width)
    xb, xf = unit.front_back, unit.front_face
    if unit.kind == "flap":  # wall unit: neighbours left and right, a front above
        col_lo, col_hi, depth = 0.0, float(kitchen.wall_unit_height), unit.depth
    else:
        col_lo = float(kitchen.plinth_height) - z0
        col_hi = col_lo + float(kitchen.carcass_height)
        depth = float(kitchen.carcass_depth)
    # the configuration's own column: carcass and fronts above and below its front
    if unit.kind == "drawer":
        fronts, slot = _drawer_stack(unit, kitchen)
        top = col_hi
        for k, h in enumerate(fronts):
            lo, hi = top - h, top
            top = lo
            if k == slot:
                continue
            # 3 mm from the configuration's front where they meet it, else half a gap each
            edge_lo = unit.height - r + g if abs(lo - unit.height) < 1e-6 else lo + g / 2
            edge_hi = r - g if abs(hi) < 1e-6 else hi - g / 2
            boxes.add(f"carcass_{k}", (-depth, -half_w, lo), (0, half_w, hi), CARCASS_RGBA)
            boxes.add(
                f"front_{k}", (xb, -half_w + r, edge_lo), (xf, half_w - r, edge_hi), FRONT_RGBA
            )
    else:
        if col_hi > unit.height + 1e-6:  # a front above the door's or flap's front
            boxes.add(
                "carcass_above", (-depth, -half_w, unit.height), (0, half_w, col_hi), CARCASS_RGBA
            )
            above = (xb, -half_w + r, unit.height - r + g), (xf, half_w - r, col_hi - g / 2)
            boxes.add("front_above", *above, FRONT_RGBA)
    # the units left and right: carcass and one tall front each, 3 mm from the configuration's
    for side in (-1, 1):
        inner, outer = side * half_w, side * (half_w + side_w)
        lo_y, hi_y = sorted((inner, outer))
        name = "left" if side < 0 else "right"
        boxes.add(f"{name}_carcass", (-depth, lo_y, col_lo), (0, hi_y, col_hi), CARCASS_RGBA)
        edge = side * (half_w - r + g)
        far = side * (half_w + side_w - g / 2)
        lo_y, hi_y = sorted((edge, far))
        boxes.add(
            f"{name}_front", (xb, lo_y, col_lo + g / 2), (xf, hi_y, col_hi - g / 2), FRONT_RGBA
        )
    run = (-half_w - side_w, half_w + side_w)
    plinth, base_depth = float(kitchen.plinth_height), float(kitchen.carcass_depth)
    base_front = 0.0 if unit.kind != "flap" else base_depth - unit.depth  # wall units recessed
    base_top = plinth + float(kitchen.carcass_height) - z0
    if unit.kind == "flap":  # the base run under the wall unit, fronts flush with its carcass
        boxes.add(
            "base_run", (base_front - base_depth, run[0], plinth - z0),
            (base_front + xf, run[1], base_top), CARCASS_RGBA,
        )  # fmt: skip
    boxes.add(
        "worktop", (base_front - base_depth - 0.02, run[0], base_top),
        (base_front + xf + float(kitchen.worktop_overhang), run[1],
         base_top + float(kitchen.worktop_thickness)), WORKTOP_RGBA,
    )  # fmt: skip
    boxes.add(
        "plinth", (base_front - base_depth + 0.02, run[0], -z0),
        (base_front - float(kitchen.toe_kick_recess), run[1], plinth - z0), PLINTH_RGBA,
    )  # fmt: skip
    return z0
