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
    """Concatenate the terms of LAYOUT (all for one environment)."""
    one_hot = np.zeros(4)
    one_hot[int(stage) - 1] = 1.0
    terms = (
        np.asarray(tcp_pos) - base_pos,
        np.asarray(tcp_rot)[:, :2].T.ravel(),
        np.asarray(handle_pos) - base_pos,
        np.asarray(handle_pos) - np.asarray(tcp_pos),
        [opening],
        [opening_vel],
        [aperture],
        [float(closed)],
        prev_action,
        one_hot,
    )
    return np.concatenate([np.asarray(t, dtype=np.float64).ravel() for t in terms])
