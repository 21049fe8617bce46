"""IK step cost: IKController.solve (mink's QP assembled in place, daqp) against mink.solve_ik.

Both take the same 2,000 steps (random targets within 1 cm and 0.04 rad of a configuration's
own pose, as the policy commands them, from configurations near home) with the same tasks and
limits; the plain path keeps its tasks between calls, as the controller did before the change.
Rounds are interleaved and the best of five is kept (thread CPU time, so other jobs on the
machine do not inflate it). Writes experiments/benchmarks/bench_ik.md.
Usage: python experiments/benchmarks/bench_ik.py
"""

from __future__ import annotations

import argparse
import platform
import time
from importlib.metadata import version
from pathlib import Path

import mink
import numpy as np

from realikea.config import load_config
from realikea.sim.ik import VELOCITY_LIMIT, IKController, tcp_pitch, tcp_rotation
from realikea.sim.robot import ARM_JOINTS, TCP_SITE

STEPS, ROUNDS = 2000, 5
OUT = Path(__file__).with_name("bench_ik.md")


class PlainMinkStep:
    """The controller's step written with mink.solve_ik (qpsolvers, daqp) and persistent tasks."""

    def __init__(self, ik: IKController):
        self.ik = ik
        self.configuration = mink.Configuration(ik.model)
        self.frame = mink.FrameTask(TCP_SITE, "site", position_cost=1.0, orientation_cost=1.0)
        self.posture = mink.PostureTask(ik.model, cost=float(ik.posture.cost[0]))
        self.posture.set_target(ik.home)
        self.limits = [
            mink.ConfigurationLimit(ik.model),
            mink.VelocityLimit(ik.model, dict(zip(ARM_JOINTS, VELOCITY_LIMIT, strict=True))),
        ]

    def solve(self, q, position, pitch: float) -> np.ndarray:
        self.configuration.update(np.clip(q, self.ik.bounds[:, 0], self.ik.bounds[:, 1]))
        rotation = mink.SO3.from_matrix(tcp_rotation(pitch, self.ik.nominal))
        self.frame.set_target(mink.SE3.from_rotation_and_translation(rotation, position))
        velocity = mink.solve_ik(
            self.configuration, [self.frame, self.posture], self.ik.dt, "daqp",
            damping=self.ik.damping, limits=self.limits,
        )  # fmt: skip
        q_new = self.configuration.integrate(velocity, self.ik.dt)
        self.configuration.update(q_new)  # the reached pose, for the tolerance check
        return q_new


def cases(ik: IKController, home: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, float]]:
    rng = np.random.default_rng(0)
    out = []
    for _ in range(STEPS):
        q = home + rng.normal(0, 0.1, 7)
        pos, rot = ik.tcp_pose(q)
        out.append(
            (q, pos + rng.uniform(-0.01, 0.01, 3), tcp_pitch(rot) + rng.uniform(-0.04, 0.04))
        )
    return out


def timed(solve, inputs) -> float:
    start = time.thread_time()
    for q, position, pitch in inputs:
        solve(q, position, pitch)
    return (time.thread_time() - start) / len(inputs)


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    cfg = load_config()
    ik = IKController.from_config(cfg)
    plain = PlainMinkStep(ik)
    inputs = cases(ik, np.asarray(cfg.sim.robot.home, float))
    same = max(float(np.max(np.abs(ik.solve(*c).q - plain.solve(*c)))) for c in inputs[:200])
    best = {"controller": np.inf, "plain": np.inf}
    for _ in range(ROUNDS):
        best["controller"] = min(best["controller"], timed(ik.solve, inputs))
        best["plain"] = min(best["plain"], timed(plain.solve, inputs))
    ratio = best["plain"] / best["controller"]
    lines = [
        "# IK step benchmark",
        "",
        "Command: `python experiments/benchmarks/bench_ik.py` (thread CPU time per call, best of "
        f"{ROUNDS} interleaved rounds of {STEPS} steps; Python {platform.python_version()}, "
        f"mink {version('mink')}, daqp {version('daqp')}).",
        "",
        "| step | µs per call |",
        "|---|---:|",
        f"| `IKController.solve` (QP in place, daqp) | {1e6 * best['controller']:.0f} |",
        f"| the same step via `mink.solve_ik` (qpsolvers, daqp) | {1e6 * best['plain']:.0f} |",
        "",
        f"Ratio, measured side by side: **{ratio:.1f}×**. Largest joint-target difference over "
        f"the first 200 steps: {same:.1e} rad (the QPs are the same; "
        "`tests/test_robot.py::test_ik_step_equals_mink_solve_ik` checks bit equality).",
    ]  # fmt: skip
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
