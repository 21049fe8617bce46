"""The privileged observation of the appendix as named terms, one flat vector per environment.

Each term maps the step's `ObservationInputs` to a list of floats; `TERMS` fixes their order and
sizes, which generate `LAYOUT`, part of a checkpoint's contract. The appendix's terms come first
(`APPENDIX_LAYOUT`, what checkpoints before the generalist were trained on); the articulation
terms after them tell one policy what it faces across categories and kinds (the joint, its axis,
where the handle moves as the front opens, the progress to success, the part's category): all
privileged facts of the scene, like the handle position. A checkpoint trained on an older layout
reads its own terms out of the current vector (`selector`).

Terms work on plain Python floats: a numpy op per term would cost more in per-call overhead than
the arithmetic (this runs once per env and control step).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from realikea.assets.catalog import CATEGORIES


class ObservationInputs(NamedTuple):
    """What the observation is made of (world frame, Python floats)."""

    tcp_pos: list[float]
    tcp_rot: list[list[float]]  # 3x3 rotation, rows
    handle_pos: list[float]
    base_pos: list[float]
    opening: float
    opening_vel: float
    aperture: float
    closed: bool
    prev_action: list[float]
    stage: int
    hinge: bool  # the front turns (door, flap) rather than slides (drawer)
    joint_axis: list[float]  # unit: the slide's direction or the hinge's axis
    pull_dir: list[float]  # unit: where the handle moves as the front opens, now
    progress: float  # opening / the success threshold of the joint type
    category: int  # index in CATEGORIES


def tcp_pos(v: ObservationInputs) -> list[float]:
    """TCP position relative to the robot base (m)."""
    (tx, ty, tz), (bx, by, bz) = v.tcp_pos, v.base_pos
    return [tx - bx, ty - by, tz - bz]


def tcp_rot6d(v: ObservationInputs) -> list[float]:
    """The first two columns of the TCP rotation matrix."""
    (r00, r01, _), (r10, r11, _), (r20, r21, _) = v.tcp_rot
    return [r00, r10, r20, r01, r11, r21]


def handle_pos(v: ObservationInputs) -> list[float]:
    """Handle position relative to the robot base (m)."""
    (hx, hy, hz), (bx, by, bz) = v.handle_pos, v.base_pos
    return [hx - bx, hy - by, hz - bz]


def handle_from_tcp(v: ObservationInputs) -> list[float]:
    """Handle - TCP (m)."""
    (hx, hy, hz), (tx, ty, tz) = v.handle_pos, v.tcp_pos
    return [hx - tx, hy - ty, hz - tz]


def opening(v: ObservationInputs) -> list[float]:
    """The front's displacement (m or rad)."""
    return [v.opening]


def opening_vel(v: ObservationInputs) -> list[float]:
    return [v.opening_vel]


def aperture(v: ObservationInputs) -> list[float]:
    """Normalized finger opening, 0 closed .. 1 open."""
    return [v.aperture]


def closed(v: ObservationInputs) -> list[float]:
    """The closure indicator s_close."""
    return [float(v.closed)]


def prev_action(v: ObservationInputs) -> list[float]:
    return list(v.prev_action)


def stage(v: ObservationInputs) -> list[float]:
    """One-hot over the four reward stages."""
    one_hot = [0.0, 0.0, 0.0, 0.0]
    one_hot[int(v.stage) - 1] = 1.0
    return one_hot


def joint_type(v: ObservationInputs) -> list[float]:
    """One-hot: slide, hinge."""
    return [0.0, 1.0] if v.hinge else [1.0, 0.0]


def joint_axis(v: ObservationInputs) -> list[float]:
    """The slide's direction or the hinge's axis (world axes, unit)."""
    return list(v.joint_axis)


def pull_dir(v: ObservationInputs) -> list[float]:
    """The direction the handle moves in as the front opens, at the current opening."""
    return list(v.pull_dir)


def progress(v: ObservationInputs) -> list[float]:
    """The opening as a fraction of success (0.2 m on a slide, 45 deg on a hinge by default)."""
    return [v.progress]


def category(v: ObservationInputs) -> list[float]:
    """One-hot over CATEGORIES (knob, two_point, finger_pull)."""
    one_hot = [0.0] * len(CATEGORIES)
    one_hot[v.category] = 1.0
    return one_hot


# (name, size, term) in the order they are concatenated
TERMS: tuple[tuple[str, int, Callable[[ObservationInputs], list[float]]], ...] = (
    ("tcp_pos", 3, tcp_pos),
    ("tcp_rot6d", 6, tcp_rot6d),
    ("handle_pos", 3, handle_pos),
    ("handle_from_tcp", 3, handle_from_tcp),
    ("opening", 1, opening),
    ("opening_vel", 1, opening_vel),
    ("aperture", 1, aperture),
    ("closed", 1, closed),
    ("prev_action", 5, prev_action),
    ("stage", 4, stage),
    ("joint_type", 2, joint_type),
    ("joint_axis", 3, joint_axis),
    ("pull_dir", 3, pull_dir),
    ("progress", 1, progress),
    ("category", len(CATEGORIES), category),
)
LAYOUT = tuple((name, size) for name, size, _ in TERMS)
APPENDIX_LAYOUT = LAYOUT[:10]  # the paper's observation: every checkpoint before the generalist
SIZE = sum(n for _, n in LAYOUT)


def slices() -> dict[str, slice]:
    """Where each named term lives in the observation vector."""
    out, start = {}, 0
    for name, n in LAYOUT:
        out[name] = slice(start, start + n)
        start += n
    return out


def selector(layout) -> np.ndarray:
    """Indices into the current observation vector that give `layout`'s vector: how a checkpoint
    trained on another (older) layout reads its own terms. Raises KeyError naming a term the
    current layout lacks or sizes differently."""
    current, where = dict(LAYOUT), slices()
    index: list[int] = []
    for name, size in layout:
        if current.get(name) != size:
            raise KeyError(f"observation term {name!r} of size {size} is not in {list(LAYOUT)}")
        index += range(where[name].start, where[name].stop)
    return np.array(index, dtype=np.intp)


def observation(inputs: ObservationInputs) -> np.ndarray:
    """Concatenate the terms of TERMS for one environment."""
    values: list[float] = []
    for _, _, term in TERMS:
        values += term(inputs)
    return np.array(values, dtype=np.float64)
