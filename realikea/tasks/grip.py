"""How the jaws hold the handle after a control step, read from the pads' poses and MuJoCo's
contacts: whether they straddle it, which fingers touch the part, and whether a finger is behind
it (hooked).

The gated reward's grasp readiness (`Grip.engaged`) is either closure the paper names:
- a pinch: the handle site between the pads and both fingers on the part, whatever the aperture
  (a knob wider than the jaws close to is grasped; closed empty jaws at the handle are not);
- form closure: a finger touching the part where its surface faces the front panel (a fingertip
  behind a bar, under a lip, behind a knob's head), so pulling presses the finger against it.
  Measured with `hook_oracle`, which hooks a closed fist behind a bar and wedges open jaws behind a
  knob's head: neither is a pinch, both open the drawer.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import mujoco
import numpy as np


class Grip(NamedTuple):
    """The jaws and the handle after a step."""

    straddle: bool  # the handle site between the pads, within the radius of the line joining them
    left: bool  # the left finger (pad or body) touches the part
    right: bool  # the right finger touches the part
    hooked: bool  # a finger touches the part where the part's surface faces the front panel
    offset: float = math.inf  # m: the handle site from the line joining the pads (inf: not between)

    @property
    def pinched(self) -> bool:
        return self.straddle and self.left and self.right

    @property
    def engaged(self) -> bool:
        return self.pinched or self.hooked


NO_GRIP = Grip(False, False, False, False)


def straddle_offset(left, right, site, inset: float) -> float:
    """The distance (m) of `site` from the line joining the pad centres `left` and `right` (3
    floats each) where it lies between the pads' inner faces, `inset` from the centres along that
    line; inf where it does not (plain floats: this runs every env-step). Closed jaws straddle
    nothing: their inner faces meet."""
    ax, ay, az = right[0] - left[0], right[1] - left[1], right[2] - left[2]
    width = math.sqrt(ax * ax + ay * ay + az * az)
    if width <= 2.0 * inset:
        return math.inf
    ax, ay, az = ax / width, ay / width, az / width
    hx, hy, hz = site[0] - left[0], site[1] - left[1], site[2] - left[2]
    along = hx * ax + hy * ay + hz * az
    if not inset < along < width - inset:
        return math.inf
    px, py, pz = hx - along * ax, hy - along * ay, hz - along * az
    return math.sqrt(px * px + py * py + pz * pz)


class GripSensor:
    """Reads `Grip` in one scene: the two pad geoms, the finger bodies and the part's body."""

    def __init__(
        self, model: mujoco.MjModel, pad_geoms: tuple[str, str], fingers: tuple[str, str], part: str
    ):
        self.model = model
        self.pads = [model.geom(g).id for g in pad_geoms]
        self.inset = float(model.geom_size[self.pads[0]][1])  # the pad's half thickness
        self.fingers = [model.body(b).id for b in fingers]
        self.part = model.body(part).id

    def read(self, data: mujoco.MjData, site, u, radius: float, hook_cos: float) -> Grip:
        """The grip after a step: `site` the handle site's position and `u` the unit direction
        the handle moves in as the front opens (3 floats each), `radius` (m) the straddle's;
        a contact hooks when the part's surface normal there has a component along -u above
        `hook_cos`."""
        xpos = data.geom_xpos
        left, right = xpos[self.pads[0]].tolist(), xpos[self.pads[1]].tolist()
        offset = straddle_offset(left, right, site, self.inset)
        touching, hooked = [False, False], False
        ncon = data.ncon
        if ncon:
            bodies = self.model.geom_bodyid[data.contact.geom[:ncon]]
            first = bodies[:, 0] == self.part  # the part is geom1: its normal is the frame's
            on_part = first | (bodies[:, 1] == self.part)
            for i, finger in enumerate(self.fingers):
                for k in np.flatnonzero(
                    on_part & ((bodies[:, 0] == finger) | (bodies[:, 1] == finger))
                ):
                    touching[i] = True
                    nx, ny, nz = data.contact.frame[k, :3].tolist()  # geom1 -> geom2
                    facing = -(nx * u[0] + ny * u[1] + nz * u[2])  # the part's normal along -u
                    if (facing if first[k] else -facing) > hook_cos:
                        hooked = True
        return Grip(offset < radius, touching[0], touching[1], hooked, offset)
