"""Can a policy open a finger-pull door on the sealed hull at all? A specialist with the
start-state curriculum, trained on the design card's geometry and resistance (hull, high), then
evaluated on the held-out finger-pull doors on its own hull (registered in README.md, "The
design card's command: can a hull finger-pull door be opened?").

    python experiments/generalist/hull_fp_door.py            # resumable: training, then cells
    python experiments/generalist/hull_fp_door.py --dry-run
    python experiments/generalist/hull_fp_door.py --park      # a stopped run's state into git

Trains in outputs/generalist_hull_fp_door/NAME (the run queue: realikea/training/queue.py),
kept in results/hull_fp_door/NAME (with its learning curve), evaluated into
results/hull_fp_door/NAME/cells.jsonl (hull, high, 50 randomized episodes on draw 1000;
`evaluate_grid`, with the contact statistics of the episodes that pulled).
"""

from __future__ import annotations

import sys
from pathlib import Path

from kept_queue import driver_arguments, kept_queue

from realikea.eval.library_grid import evaluate_grid
from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE
from realikea.training.queue import QueuedRun

HERE = Path(__file__).resolve().parent
KEPT = HERE / "results/hull_fp_door"
PARKED = HERE / "results/hull_fp_door_parked"
WORK = WORKSPACE / "outputs/generalist_hull_fp_door"
ITERATIONS, SWITCH, SHARE, SEED = 600, 300, 0.5, 220
CELL = ("collision=hull", "resistance=high", "asset=finger_pull", "asset.kind=door")
RUN = QueuedRun(
    "specialist_pregrasp_s220",
    ("logger=none", *CELL, f"+task.pregrasp_share={SHARE}", f"env.seed={SEED}",
     f"agent.max_iterations={ITERATIONS}", f"dr.switch_iteration={SWITCH}"),
    ITERATIONS,
)  # fmt: skip


def main(argv: list[str]) -> int:
    args = driver_arguments(__doc__, argv)
    queue = kept_queue(WORK, KEPT, PARKED)
    status = queue.serve([RUN], 1, dry_run=args.dry_run, park=args.park)
    if status or args.dry_run or args.park or not queue.kept(RUN):
        return status
    evaluate_grid(
        checkpoints(KEPT / RUN.name)[-1][1], KEPT / RUN.name / "cells.jsonl",
        kinds=("door",), categories=("finger_pull",), modes=("high",), extra=["collision=hull"],
    )  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
