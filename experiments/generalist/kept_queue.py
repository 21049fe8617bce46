"""What a one-folder training driver shares: its `--dry-run` / `--park` arguments, and a run queue
(realikea/training/queue.py) that keeps each finished run in one results folder with its
learning curve."""

from __future__ import annotations

import argparse
from pathlib import Path

from realikea.reports.learning_curve import plot_learning_curve
from realikea.training.queue import RunQueue, keep_run


def driver_arguments(doc: str, argv: list[str]) -> argparse.Namespace:
    """A driver's command line: `--dry-run` and `--park`, described by its docstring's head."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--dry-run", action="store_true", help="print the runs and stop")
    parser.add_argument("--park", action="store_true", help="stop at next checkpoints; copy to git")
    return parser.parse_args(argv)


def kept_queue(work: Path, kept: Path, parked: Path) -> RunQueue:
    """Runs trained in `work/NAME` to their last iteration, kept in `kept/NAME` (slim checkpoint,
    metrics, wall time) with their learning curves; stopped ones parked in `parked`."""
    return RunQueue(
        work,
        lambda run: f"model_{run.iterations - 1}.pt",
        lambda run, seconds: plot_learning_curve(
            keep_run(work / run.name, kept / run.name, seconds)
        ),
        lambda run: (kept / run.name / "wall.json").is_file(),
        parked=parked,
    )
