"""Reach study: the TCP pitch range the Panda's joint limits allow at a handle, by height and
distance from the arm's base, for the level hand (drawers, flap) and the hand rolled 90 deg
(doors). The numbers behind the kitchen's robot placement (realikea/conf/scene/kitchen.yaml:
robot) and the hand's roll choice on hinged fronts (realikea/tasks/open_task.py: _hand_roll).

Method: from the home posture, walk the TCP to the point in 1 cm IK steps at pitch 0 (as a policy
would), then raise or lower the pitch in 0.04 rad steps (the task's action scale) while the IK
stays feasible. Prints `down/up` (rad) per point; `x` where the point itself was not reached.

    python experiments/reach/reach.py
"""

import argparse
import math

import numpy as np

from realikea.config import load_config
from realikea.sim.ik import IKController, rolled_nominal


def reach(home, dx: float, h: float, roll: float, sign: int) -> float | None:
    """The largest pitch (signed) reachable at (dx in front of the base, h above it)."""
    nominal = rolled_nominal(roll)
    ik = IKController(base_pos=(0, 0, 0), base_yaw=math.pi, home=home, nominal=nominal)
    q = home.copy()
    if roll:
        position, _ = ik.tcp_pose(home)
        q = ik.converge(home, position, 0.0)
    ik = IKController(base_pos=(0, 0, 0), base_yaw=math.pi, home=q, nominal=nominal)
    target = np.array([-dx, 0.0, h])
    for _ in range(150):
        position, _ = ik.tcp_pose(q)
        step = target - position
        norm = np.linalg.norm(step)
        q = ik.solve(q, position + step * min(1, 0.01 / max(norm, 1e-9)), 0.0).q
        if norm < 1e-3:
            break
    position, _ = ik.tcp_pose(q)
    if np.linalg.norm(position - target) > 0.005:
        return None
    best = 0.0
    for k in range(1, 45):
        pitch = sign * 0.04 * k
        for _ in range(4):
            result = ik.solve(q, target, pitch)
            q = result.q
            if result.ok:
                break
        else:
            break
        best = pitch
    return best


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    home = np.asarray(load_config([]).sim.robot.home, float)
    heights = (0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
    for roll in (0.0, math.pi / 2):
        print(f"roll {math.degrees(roll):.0f} deg: rows dx (m in front of the base), columns h")
        print("dx    " + " ".join(f"{h:>12}" for h in heights))
        for dx in (0.55, 0.60, 0.65, 0.75):
            cells = []
            for h in heights:
                up, down = reach(home, dx, h, roll, 1), reach(home, dx, h, roll, -1)
                cells.append("x" if up is None else f"{down:+.2f}/{up:+.2f}")
            print(f"{dx:<5} " + " ".join(f"{c:>12}" for c in cells), flush=True)


if __name__ == "__main__":
    main()
