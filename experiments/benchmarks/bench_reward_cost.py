"""What a reward variant costs per control step: one task (a two-point drawer, fixed pose) stepping
600 random actions in this process under each variant, alternated twice, then the reward side
alone (reading the step's values and the weighted terms) 2,000 times on the last state.

    python experiments/benchmarks/bench_reward_cost.py

Prints steps/s and microseconds of reward-side work per step for each variant.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.tasks.open_task import OpenTask


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    for variant in ("appendix", "gated", "appendix", "gated"):
        cfg = load_config(
            ["asset=two_point", "asset.kind=drawer", "dr=fixed", f"task/reward={variant}"]
        )
        task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
        rng = np.random.default_rng(0)
        task.reset()
        begin = time.perf_counter()
        for _ in range(600):
            result = task.step(rng.uniform(-1, 1, 5))
            if result.terminated or result.truncated:
                task.reset()
        rate = 600 / (time.perf_counter() - begin)
        begin = time.perf_counter()
        for _ in range(2000):
            values = task._step_values(task.state.stage, [0.0] * 5, True)
            task.reward.weighted_terms(values, task.params)
        reward_us = 1e6 * (time.perf_counter() - begin) / 2000
        print(f"{variant}: {rate:.0f} steps/s, reward side {reward_us:.1f} us a step")


if __name__ == "__main__":
    main()
