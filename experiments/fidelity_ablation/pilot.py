"""The grid's pilot: does today's default recipe learn under today's kitchen placements, on
seeds the project never used, before the fidelity grid (v2) freezes it?

    python experiments/fidelity_ablation/pilot.py            # every run not yet kept, two at a time
    python experiments/fidelity_ablation/pilot.py --dry-run  # the commands and their state
    python experiments/fidelity_ablation/pilot.py --placements none  # arm 0.80 m below (screened)
    python experiments/fidelity_ablation/pilot.py --park     # stop at next checkpoints, into git

Knob x high and finger pull x smooth, drawers, kitchen, train parts, CoACD and hull, seeds 12
and 13, on the grid's schedule (600 iterations, fixed poses to 300, then randomized), one env
worker a run. A run stops once a full LEARNED_WINDOW-iteration window on randomized poses
averages at least LEARNED training success (it has learned and holds it off the fixed poses);
otherwise it runs its 600 iterations. Each finished run is kept in
experiments/fidelity_ablation/results/grid_v2/pilot/NAME (config, metrics, slim last checkpoint,
wall time); a stopped run resumes from its last checkpoint (realikea/training/queue.py), on
another machine from results/grid_v2/pilot_parked/NAME (`--park` before the session ends).
The table: `python experiments/fidelity_ablation/pilot_report.py`.
"""

from __future__ import annotations

import argparse
import itertools
import sys

import numpy as np

from realikea.files import WORKSPACE
from realikea.sources import SOURCES
from realikea.training.metrics import read_metrics
from realikea.training.queue import QueuedRun, RunQueue, keep_run

KEPT = WORKSPACE / "experiments/fidelity_ablation/results/grid_v2/pilot"
PARKED = WORKSPACE / "experiments/fidelity_ablation/results/grid_v2/pilot_parked"
WORK = WORKSPACE / "outputs/grid_v2_pilot"
ITERATIONS = 600
SWITCH = 300  # fixed poses before this iteration, randomized from it
LEARNED, LEARNED_WINDOW = 0.5, 20  # a full window of training success at or above LEARNED
CELLS = {"knob_high": ("knob", "high"), "finger_pull_smooth": ("finger_pull", "smooth")}
COLLISIONS = SOURCES
SEEDS = (12, 13)
# placement name -> the overrides that make it ("today": the kitchen's defaults)
PLACEMENTS = {"today": [], "none": ["scene.robot.placements=[]"]}
COMMON = [
    "asset.kind=drawer", "scene=kitchen", "logger=none", "env.num_workers=1",
    f"agent.max_iterations={ITERATIONS}", "agent.save_interval=10", "dr=two_phase",
    f"dr.switch_iteration={SWITCH}",
]  # fmt: skip


def pilot_run(collision: str, cell: str, seed: int, placement: str) -> QueuedRun:
    category, resistance = CELLS[cell]
    overrides = [f"collision={collision}", f"asset={category}", f"resistance={resistance}"]
    overrides += [f"env.seed={seed}", *COMMON, *PLACEMENTS[placement]]
    suffix = "" if placement == "today" else f"_{placement}"
    return QueuedRun(f"{collision}_{cell}_s{seed}{suffix}", tuple(overrides), ITERATIONS)


def series(metrics, tag: str) -> tuple[np.ndarray, np.ndarray]:
    """(iterations, values) of a tag, each iteration as its last launch logged it."""
    its, values = metrics.get(tag, ([], []))
    by_iteration = dict(zip(its, values, strict=True))  # a resumed launch's rows replace earlier
    order = sorted(by_iteration)
    return np.array(order, dtype=int), np.array([by_iteration[i] for i in order])


def first_full_window(its: np.ndarray, values: np.ndarray, start: int = 0) -> int | None:
    """The first iteration >= start whose full LEARNED_WINDOW-iteration window reaches LEARNED."""
    chosen = its >= start
    its, values = its[chosen], values[chosen]
    if len(values) < LEARNED_WINDOW:
        return None
    means = np.convolve(values, np.ones(LEARNED_WINDOW), mode="valid") / LEARNED_WINDOW
    hits = np.flatnonzero(means >= LEARNED)
    return int(its[hits[0]]) if len(hits) else None


def learned_on_randomized(run: QueuedRun) -> bool:
    """Whether a full LEARNED_WINDOW-iteration window, all on randomized poses, averages at
    least LEARNED training success."""
    metrics = WORK / run.name / "metrics.csv"
    if not metrics.is_file():
        return False
    its, values = series(read_metrics(metrics.parent), "/episode/success")
    return first_full_window(its, values, SWITCH) is not None


QUEUE = RunQueue(
    WORK,
    lambda run: f"model_{run.iterations - 1}.pt",
    lambda run, seconds: keep_run(WORK / run.name, KEPT / run.name, seconds),
    lambda run: (KEPT / run.name / "wall.json").is_file(),  # keep_run writes the folder whole
    stop_early=learned_on_randomized,
    parked=PARKED,
)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cells", nargs="+", choices=list(CELLS), default=list(CELLS))
    parser.add_argument("--collisions", nargs="+", choices=COLLISIONS, default=list(COLLISIONS))
    parser.add_argument("--seeds", nargs="+", type=int, default=list(SEEDS))
    parser.add_argument("--placements", choices=list(PLACEMENTS), default="today")
    parser.add_argument("--jobs", type=int, default=2, help="runs side by side (2 cores: 2)")
    parser.add_argument("--dry-run", action="store_true", help="print the commands only")
    parser.add_argument("--park", action="store_true", help="stop at next checkpoints; copy to git")
    args = parser.parse_args()
    runs = [
        pilot_run(collision, cell, seed, args.placements)
        for seed, cell, collision in itertools.product(args.seeds, args.cells, args.collisions)
    ]
    return QUEUE.serve(runs, args.jobs, args.dry_run, args.park)


if __name__ == "__main__":
    sys.exit(main())
