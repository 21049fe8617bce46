"""Where the fidelity grid's runs that never learned ended, from their committed metrics.csv:
the measurements behind the gated reward (experiments/reward_screen/README.md).

    python experiments/reward_screen/grid_traps.py [--grid DIR]

For each of the grid's 900-iteration runs (not the paper's schedule): whether it learned (the
training success, averaged over 20 iterations, reached 0.5), and for those that did not the
reward per step (Train/mean_reward / Train/mean_episode_length) and the mean opening over
iterations 880-899; then how many of the first iterations finished no episode at all (no
/episode/success logged), and the range of the runs' median value loss. Prints markdown.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from realikea.files import WORKSPACE
from realikea.runs.curves import iterations_to_success
from realikea.training.metrics import read_metrics

LAST = (880, 899)  # the iterations read for where a run ended
FIRST = 20  # the first iterations checked for finished episodes


def window(series, tag: str, first: int, last: int) -> float:
    its, values = (np.asarray(x, float) for x in series[tag])
    return float(values[(its >= first) & (its <= last)].mean())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--grid", type=Path, default=WORKSPACE / "experiments/fidelity_ablation/results/grid"
    )
    args = parser.parse_args()
    runs = sorted(p for p in args.grid.iterdir()
                  if (p / "metrics.csv").is_file() and not p.name.startswith("paper_"))  # fmt: skip
    rows, idle, value_losses = [], 0, []
    for path in runs:
        series = read_metrics(path)
        value_losses.append(float(np.median(series["Loss/value"][1])))
        idle += FIRST - len({i for i in series["/episode/success"][0] if i < FIRST})
        if iterations_to_success({"metrics": series}) is not None:
            continue
        per_step = window(series, "Train/mean_reward", *LAST) / window(
            series, "Train/mean_episode_length", *LAST
        )
        rows.append((per_step, window(series, "/episode/opening", *LAST), path.name))
    print(f"{len(rows)} of {len(runs)} runs never reached 50 % training success; "
          f"iterations {LAST[0]}-{LAST[1]}:\n")  # fmt: skip
    print("| run | reward a step | opening (m) |\n|---|---:|---:|")
    for per_step, opening, name in sorted(rows):
        print(f"| {name} | {per_step:.1f} | {opening:.3f} |")
    print(f"\nIterations 0-{FIRST - 1}: {idle} of {FIRST * len(runs)} finished no episode.")
    print(f"Median value loss of a run: {min(value_losses):.0f} to {max(value_losses):.0f}.")


if __name__ == "__main__":
    main()
