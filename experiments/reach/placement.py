"""Home postures for a kitchen placement, found by a global search: the level hand `--back` m in
front of a handle `--dx` m out and `--above` m over the arm's base, reached by IK from random
joint seeds; from each posture the TCP walks to the handle in 1 cm steps and its pitch is raised
and lowered in the task's 0.04 rad steps while the IK stays feasible. Prints the postures with
the widest upward range (then the largest margin to a joint limit): the numbers behind
realikea/conf/scene/kitchen.yaml's `robot.placements`.

    python experiments/reach/placement.py --above 0.15 0.80
"""

from __future__ import annotations

import argparse
import itertools
import math

import numpy as np

from realikea.errors import RealIkeaError
from realikea.sim.ik import IKController, rolled_nominal
from realikea.sim.robot import joint_limits

STEP = 0.04  # rad per pitch step (realikea/conf/task/open.yaml: action.pitch_scale)


def controller(home: np.ndarray) -> IKController:
    return IKController(base_pos=(0, 0, 0), base_yaw=math.pi, home=home, nominal=rolled_nominal(0))


def pitch_range(home: np.ndarray, handle: np.ndarray) -> tuple[float, float] | None:
    """(down, up) pitch the joint limits allow at the handle, walked to from `home`."""
    ik, q = controller(home), home.copy()
    for _ in range(100):
        position, _ = ik.tcp_pose(q)
        step = handle - position
        norm = float(np.linalg.norm(step))
        q = ik.solve(q, position + step * min(1.0, 0.01 / max(norm, 1e-9)), 0.0).q
        if norm < 1e-3:
            break
    if np.linalg.norm(ik.tcp_pose(q)[0] - handle) > 3e-3:
        return None
    reached = []
    for sign in (-1, 1):
        at, best = q.copy(), 0.0
        for k in range(1, 41):
            for _ in range(4):
                result = ik.solve(at, handle, sign * STEP * k)
                at = result.q
                if result.ok:
                    break
            else:
                break
            best = sign * STEP * k
        reached.append(best)
    return reached[0], reached[1]


def search(above: float, dx: float, back: float, seeds: int, rng) -> list[tuple]:
    """(up, down, margin, posture) of every seed that converged, widest upward range first."""
    lo, hi = joint_limits().T
    start = np.array([-(dx - back), 0.0, above])
    handle = np.array([-dx, 0.0, above])
    found = []
    for _ in range(seeds):
        seed = rng.uniform(lo, hi)
        try:
            home = controller(seed).converge(seed, start, 0.0, steps=400)
        except RealIkeaError:
            continue
        span = pitch_range(home, handle)
        if span is not None:
            margin = float(np.min(np.minimum(home - lo, hi - home)))
            found.append((span[1], span[0], margin, home))
    return sorted(found, key=lambda f: (-f[0], -f[2]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--above", nargs="+", type=float, default=[0.15, 0.80])
    parser.add_argument(
        "--dx", nargs="+", type=float, default=[0.60], help="m from the base to the handle"
    )
    parser.add_argument("--back", type=float, default=0.15, help="m the home stands back")
    parser.add_argument("--seeds", type=int, default=60)
    parser.add_argument("--show", type=int, default=3)
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    print(f"home {args.back} m in front of the handle, {args.seeds} seeds\n")
    print(
        "| handle above base (m) | dx (m) | converged | up (rad) | down (rad) | margin (rad) "
        "| posture |"
    )
    print("|---:|---:|---:|---:|---:|---:|---|")
    for above, dx in itertools.product(args.above, args.dx):
        found = search(above, dx, args.back, args.seeds, rng)
        for up, down, margin, home in found[: args.show]:
            posture = ", ".join(f"{v:.3f}" for v in home)
            cells = f"{up:+.2f} | {down:+.2f} | {margin:.2f} | {posture}"
            print(f"| {above} | {dx} | {len(found)} | {cells} |")


if __name__ == "__main__":
    main()
