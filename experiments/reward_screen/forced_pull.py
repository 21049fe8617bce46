"""What a kept screen policy's grasp does when made to pull: the policy runs on training parts of
its own cell (randomized poses); from step FROM on, its translation command along the opening
direction is replaced by a fixed pull (the rest of its command kept). Prints a markdown table:
per configuration and pull, the opening at the episode's end, the stage then, and the steps the
episode lasted (120 unless a termination ended it).

    python experiments/reward_screen/forced_pull.py gated_push_hull_two_point_smooth_s1
"""

from __future__ import annotations

import argparse

from realikea.assets.library import training_configurations
from realikea.errors import RealIkeaError
from realikea.eval.setup import eval_setup, trained_cell
from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE
from realikea.policies.rollout import episode
from realikea.tasks.open_task import OpenTask

RUNS = WORKSPACE / "experiments/reward_screen/results/runs"
CONFIGURATIONS = 3
FROM = 35  # step from which the pull is forced (the kept policies grasp by step 20-30)
PULLS = (None, 0.5, 1.0)  # None: the policy's own command; else the command along the opening


def forced_episode(task: OpenTask, policy, pull: float | None) -> tuple[float, int, int]:
    """(opening, final stage, steps) of one episode with the pull forced from FROM on."""

    def steer(t: int, action):
        if pull is not None and t >= FROM:
            u = task.pull_direction()
            move = action[1:4]
            action[1:4] = move - move.dot(u) * u + pull * u
        return action

    results = list(episode(task, policy, steer))
    return task.opening, results[-1].info["stage"], len(results)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "run", help="a kept run's name (experiments/reward_screen/results/runs/NAME)"
    )
    args = parser.parse_args()
    folder = RUNS / args.run
    try:
        _, path = checkpoints(folder)[-1]
        cell = trained_cell(folder)
    except RealIkeaError as err:
        parser.error(str(err))
    overrides = [*cell, f"policy.path={path}", "asset.split=train", "dr=randomized"]
    cfg, policy = eval_setup(["policy=checkpoint", *overrides])
    print(f"{args.run} ({path.name}), training parts, randomized poses; pull forced from "
          f"step {FROM}")  # fmt: skip
    print("| configuration | pull command | opening (m) | stage at the end | steps |")
    print("|---|---|---:|---:|---:|")
    for k, configuration in enumerate(training_configurations(cfg, CONFIGURATIONS, 0)):
        for pull in PULLS:
            task = OpenTask(cfg, configuration, seed=k)
            opening, stage, steps = forced_episode(task, policy, pull)
            label = "the policy's" if pull is None else f"{pull:.1f}"
            print(f"| {k} | {label} | {opening:.3f} | {stage} | {steps} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
