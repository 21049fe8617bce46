"""How hard each kept screen policy presses the closed front shut: its slim last checkpoint run
on training parts of its own cell (randomized poses, as after the switch), episode by episode in
one process, reading the force the front's closed stop holds against
(`OpenTask.pressing_force`, N at the handle). Prints a markdown table.

    python experiments/reward_screen/pressing.py                 # every kept run's checkpoint
    python experiments/reward_screen/pressing.py --runs gated_hull_two_point_smooth_s1

Per run: the share of episodes that succeed, and over the steps after the first 20 (the
approach), the share of steps pressing with more than PRESSING newtons and their median force.
"""

from __future__ import annotations

import argparse
import statistics
import sys

from tqdm import tqdm

from realikea.assets.library import training_configurations
from realikea.eval.setup import eval_setup, trained_cell
from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE
from realikea.policies.rollout import episode
from realikea.tasks.open_task import OpenTask

RUNS = WORKSPACE / "experiments/reward_screen/results/runs"
EPISODES = 6  # configurations of the run's cell, one episode each
APPROACH = 20  # steps left out at the start of an episode
PRESSING = 50.0  # N: a step presses the closed front above this


def measure(run: str, episodes: int) -> dict:
    """Success share, pressing share and median pressing force of one run's policy."""
    _, path = checkpoints(RUNS / run)[-1]
    cell = trained_cell(RUNS / run)
    overrides = [*cell, f"policy.path={path}", "asset.split=train", "dr=randomized", "env.seed=0"]
    cfg, policy = eval_setup(["policy=checkpoint", *overrides])
    configurations = training_configurations(cfg, episodes, 0)
    successes, forces, steps = 0, [], 0
    for k, configuration in enumerate(configurations):
        task = OpenTask(cfg, configuration, seed=k)
        for t, result in enumerate(episode(task, policy)):
            info = result.info  # the last step's once the loop ends
            if t >= APPROACH:
                steps += 1
                push = task.pressing_force()
                if push > PRESSING:
                    forces.append(push)
        successes += info["outcome"] == "success"
    return {
        "checkpoint": path.name,
        "success": successes / len(configurations),
        "pressing": len(forces) / max(steps, 1),
        "median": statistics.median(forces) if forces else 0.0,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--runs", nargs="+", help="kept run names (default: every one with a checkpoint)"
    )
    parser.add_argument("--episodes", type=int, default=EPISODES)
    args = parser.parse_args()
    kept = sorted(
        p.name for p in RUNS.iterdir() if (p / "wall.json").is_file() and any(p.glob("model_*.pt"))
    )  # a superseded recipe's run keeps no checkpoint
    runs = args.runs or kept
    unknown = [r for r in runs if r not in kept]
    if unknown:
        parser.error(f"not kept with a checkpoint: {', '.join(unknown)} (kept: {', '.join(kept)})")
    if args.episodes < 1:
        parser.error(f"--episodes must be >= 1, got {args.episodes}")
    print(f"training parts, randomized poses, {args.episodes} configurations a run (seed 0)")
    print(f"| run | checkpoint | success | steps pressing > {PRESSING:.0f} N | median force (N) |")
    print("|---|---|---:|---:|---:|")
    for run in tqdm(runs, desc="runs", file=sys.stderr):
        m = measure(run, args.episodes)
        print(
            f"| {run} | {m['checkpoint']} | {m['success']:.2f} | {m['pressing']:.2f} "
            f"| {m['median']:.0f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
