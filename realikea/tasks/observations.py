"""The privileged observation of the appendix, as one flat vector per environment."""

from __future__ import annotations

import numpy as np

# name -> size, in the order they are concatenated; the layout is part of a checkpoint's contract
LAYOUT = (
    ("tcp_pos", 3),  # TCP position relative to the robot base (m)
    ("tcp_rot6d", 6),  # first two columns of the TCP rotation matrix
    ("handle_pos", 3),  # handle position relative to the robot base (m)
    ("handle_from_tcp", 3),  # handle - TCP (m)
    ("opening", 1),  # articulation displacement (m or rad)
    ("opening_vel", 1),  # its rate
    ("aperture", 1),  # normalized finger opening, 0 closed .. 1 open
    ("closed", 1),  # closure indicator s_close
    ("prev_action", 5),
    ("stage", 4),  # one-hot over the four reward stages
)
SIZE = sum(n for _, n in LAYOUT)


def slices() -> dict[str, slice]:
    """Where each named term lives in the observation vector."""
    out, start = {}, 0
    for name, n in LAYOUT:
        out[name] = slice(start, start + n)
        start += n
    return out


def observation(
    tcp_pos,
    tcp_rot,
    handle_pos,
    base_pos,
    opening,
    opening_vel,
    aperture,
    closed,
    prev_action,
    stage,
) -> np.ndarray:
    """Concatenate the terms of LAYOUT (all for one environment).

    Assembled from Python floats into one array: a vector op per term would cost more in numpy's
    per-call overhead than the arithmetic (this runs once per env and control step).
    """
    tx, ty, tz = np.asarray(tcp_pos).tolist()
    hx, hy, hz = np.asarray(handle_pos).tolist()
    bx, by, bz = np.asarray(base_pos).tolist()
    (r00, r01, _), (r10, r11, _), (r20, r21, _) = np.asarray(tcp_rot).tolist()
    one_hot = [0.0, 0.0, 0.0, 0.0]
    one_hot[int(stage) - 1] = 1.0
    return np.array(
        [
            tx - bx, ty - by, tz - bz,  # tcp_pos
            r00, r10, r20, r01, r11, r21,  # tcp_rot6d: columns 0 and 1
            hx - bx, hy - by, hz - bz,  # handle_pos
            hx - tx, hy - ty, hz - tz,  # handle_from_tcp
            opening, opening_vel, aperture, float(closed),
            *np.asarray(prev_action).tolist(),
            *one_hot,
        ],
        dtype=np.float64,
    )  # fmt: skip
