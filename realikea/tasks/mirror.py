"""A door's observation and action reflected into its hinge twin's, so a policy sees every door
of a category as hinged on one side (left-hinged doors as right-hinged ones; finger-pull doors,
whose placement turns the hand, the other way: `open_task._mirrored_door`).

The scene mirrors in the vertical plane through the robot base (the world's x-z plane): the
robot stands at the mirrored place before a door of the other hinge side, its arm starts from
the mirrored posture (`open_task.MIRRORED_JOINTS`) and its hand is turned a half turn
(`open_task._hand_roll`). Reflected, such a door's observation is its twin's, and an action
the policy means for the twin is reflected before it drives the arm (`tests/test_mirror.py`
rolls twins side by side). Every term is a sign per entry:

- positions and directions (polar vectors): y negated;
- the TCP rotation R: the world's y reflected and the hand's own x (the half turn's trace),
  R' = diag(1, -1, 1) R diag(-1, 1, 1), so the first two columns' entries take those signs;
- the hinge axis (an axial vector): x and z negated, so a left hinge's axis is a right one's;
- the previous action: the action's reflection (below); scalars and one-hots unchanged.

The action's lateral translation (a2, world y) is negated. The wrist pitch, a turn about the
hand's own x axis (`realikea.sim.ik.tcp_rotation`), is unchanged: diag(-1, 1, 1) commutes with a
turn about x. The other translations and the gripper are unchanged.
"""

from __future__ import annotations

import numpy as np

from realikea.tasks import observations

ACTION_SIGNS = np.array([1.0, 1.0, -1.0, 1.0, 1.0])  # pitch, x, y, z, gripper

_Y = [1.0, -1.0, 1.0]
TERM_SIGNS = {
    "tcp_pos": _Y,
    "tcp_rot6d": [-1.0, 1.0, -1.0, 1.0, -1.0, 1.0],  # diag(1,-1,1) R diag(-1,1,1), columns 0, 1
    "handle_pos": _Y,
    "handle_from_tcp": _Y,
    "prev_action": ACTION_SIGNS.tolist(),
    "joint_axis": [-1.0, 1.0, -1.0],
    "pull_dir": _Y,
}


def observation_signs() -> np.ndarray:
    """The reflection as a sign per entry of the observation vector (`observations.LAYOUT`)."""
    signs = []
    for name, size in observations.LAYOUT:
        term = TERM_SIGNS.get(name, [1.0] * size)
        if len(term) != size:  # a term whose size changed without its reflection
            raise ValueError(f"mirror signs of {name!r}: {len(term)} for a term of size {size}")
        signs.extend(term)
    return np.array(signs)


OBSERVATION_SIGNS = observation_signs()
