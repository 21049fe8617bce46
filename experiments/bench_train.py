"""Wall-clock to a training-success target: run `python train.py OVERRIDES`, then read its
metrics.csv for the first iteration whose success (mean over the last WINDOW iterations)
reaches TARGET, and the wall time to it.

    python experiments/bench_train.py NAME [--target 0.8] [--tag /episode/success] \
        [--window 10] -- OVERRIDES...

The run goes to outputs/bench_train/NAME. Time to an iteration is the process's start-up
(composing, building missing configurations, starting the pool: the wall time before the first
iteration) plus rsl-rl's own collection and learning times of every iteration up to it. Prints
one markdown row; record it, with the machine's load, in experiments/bench_train.md.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from realikea.files import WORKSPACE
from realikea.reports.metrics import read_metrics


def time_to_target(series, tag: str, target: float, window: int):
    """(iteration, seconds of training to it) of the first window mean >= target, or None."""
    its, values = series.get(tag, ([], []))
    collect = dict(zip(*series["Perf/collection_time"], strict=True))
    learn = dict(zip(*series["Perf/learning_time"], strict=True))
    for i in range(len(values)):
        if i + 1 >= window and np.mean(values[i + 1 - window : i + 1]) >= target:
            spent = sum(collect[j] + learn[j] for j in collect if j <= its[i])
            return its[i], spent
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("name")
    parser.add_argument("--target", type=float, default=0.8)
    parser.add_argument("--tag", default="/episode/success")
    parser.add_argument("--window", type=int, default=10)
    parser.add_argument("overrides", nargs="*")
    args = parser.parse_args()
    run = WORKSPACE / "outputs" / "bench_train" / args.name
    command = [sys.executable, "train.py", *args.overrides, "logger=none", f"hydra.run.dir={run}"]
    start = time.perf_counter()
    subprocess.run(command, cwd=WORKSPACE, check=True)
    wall = time.perf_counter() - start
    series = read_metrics(Path(run))
    spent = sum(series["Perf/collection_time"][1]) + sum(series["Perf/learning_time"][1])
    startup = wall - spent
    last = series["Perf/collection_time"][0][-1]
    hit = time_to_target(series, args.tag, args.target, args.window)
    reached = (
        f"{hit[0]} | {(startup + hit[1]) / 60:.1f}"
        if hit
        else f"not reached in {last + 1} | > {wall / 60:.1f}"
    )
    load = os.getloadavg()[0]
    print(
        f"| `{' '.join(args.overrides)}` | {args.tag} ≥ {args.target} ({args.window}-it mean) | "
        f"{reached} | {wall / 60:.1f} ({last + 1} it) | {startup:.0f} | {load:.1f} |"
    )


if __name__ == "__main__":
    main()
