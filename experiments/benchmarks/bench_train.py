"""Wall-clock to a training-success target: run `python train.py OVERRIDES` for each named run,
side by side, then read each metrics.csv for the first iteration whose success (mean over the
last WINDOW iterations) reaches TARGET, and the wall time to it.

    python experiments/benchmarks/bench_train.py --run NAME "OVERRIDES" \
        [--run NAME2 "OVERRIDES2" ...] [--target 0.8] [--tag /episode/success] [--window 10]

Runs given together start together and share the machine, so their times compare as a ratio
even on a loaded machine; give each `env.num_workers=1` to split the 2 cores evenly. Each run
goes to outputs/bench_train/NAME. Time to an iteration is the process's start-up (composing,
building missing configurations, starting the pool: the wall time before the first iteration)
plus rsl-rl's own collection and learning times of every iteration up to it. Prints one
markdown row per run; record them, with the machine's load, in
experiments/benchmarks/bench_train.md.
"""

from __future__ import annotations

import argparse
import os
import shlex
import subprocess
import sys
import time

import numpy as np

from realikea.files import WORKSPACE
from realikea.training.metrics import read_metrics

RUNS = WORKSPACE / "outputs" / "bench_train"  # one folder per named run


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


def row(name: str, overrides: list[str], wall: float, args: argparse.Namespace) -> str:
    """The markdown row of one finished run."""
    series = read_metrics(RUNS / name)
    spent = sum(series["Perf/collection_time"][1]) + sum(series["Perf/learning_time"][1])
    startup = wall - spent
    last = series["Perf/collection_time"][0][-1]
    hit = time_to_target(series, args.tag, args.target, args.window)
    reached = (
        f"{hit[0]} | {(startup + hit[1]) / 60:.1f}"
        if hit
        else f"not reached in {last + 1} | > {wall / 60:.1f}"
    )
    return (
        f"| {name} | `{' '.join(overrides)}` | {args.tag} ≥ {args.target} ({args.window}-it "
        f"mean) | {reached} | {wall / 60:.1f} ({last + 1} it) | {startup:.0f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--run", nargs=2, action="append", required=True, metavar=("NAME", "OVERRIDES")
    )
    parser.add_argument("--target", type=float, default=0.8)
    parser.add_argument("--tag", default="/episode/success")
    parser.add_argument("--window", type=int, default=10)
    args = parser.parse_args()
    names = [name for name, _ in args.run]
    if len(set(names)) != len(names):
        parser.error(f"--run names must differ, got {names}")
    runs = {name: shlex.split(overrides) for name, overrides in args.run}
    taken = [name for name in runs if (RUNS / name).exists()]
    if taken:  # train.py appends to a run's metrics.csv, which would mix two launches' rows
        parser.error(f"outputs/bench_train/ already holds {taken}: remove them or pick new names")
    start, procs, walls = time.perf_counter(), {}, {}
    for name, overrides in runs.items():
        command = [
            sys.executable,
            "train.py",
            *overrides,
            "logger=none",
            f"hydra.run.dir={RUNS / name}",
        ]
        procs[name] = subprocess.Popen(command, cwd=WORKSPACE)
    while len(walls) < len(procs):
        for name, proc in procs.items():
            if name not in walls and proc.poll() is not None:
                if proc.returncode:
                    sys.exit(f"{name}: train.py exited with {proc.returncode}")
                walls[name] = time.perf_counter() - start
        time.sleep(1.0)
    print("| run | overrides | target | iteration reached | minutes to it (start-up included) "
          "| whole run | start-up (s) |")  # fmt: skip
    print("|---|---|---|---:|---:|---:|---:|")
    for name, overrides in runs.items():
        print(row(name, overrides, walls[name], args))
    print(f"load average at the end: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
