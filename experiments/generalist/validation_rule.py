"""The screen's validation rule (round 20 on): each kept run's student (its last checkpoint) on
the validation draw, its mean action, every category x kind group in smooth and high; a run
passes if every group opens at least the mark of its mode, and the candidate is adopted if
every run passes.

    python experiments/generalist/validation_rule.py RESULTS/screen/NAME_s20 RESULTS/screen/NAME_s21

Train parts, `env.seed=2000` (the sweep's validation seed, never the test draw), randomized
poses, 50 episodes a cell, the collision source and scene the run trained on; each cell's
record (`evaluate_grid`) is appended to RUN/validation_cells.jsonl as it comes, so a stopped
rule evaluates only what is missing. Prints a table per run (Wilson 95 % intervals, ✗ under the
mark) and the verdict. Exit 0, or 2 on bad input (checked for every run before any evaluation).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, group_name
from realikea.eval.library_grid import evaluate_grid
from realikea.eval.stats import wilson
from realikea.eval.sweep import VALIDATION_SEED, checkpoints
from realikea.policies.checkpoint import run_config

MARKS = {"smooth": 0.8, "high": 0.7}  # the aims' marks, read here on the validation draw
EPISODES = 50
CELLS = "validation_cells.jsonl"


def student(run: Path) -> Path:
    """The run's last checkpoint; raises ValueError naming a folder without one."""
    if not run.is_dir() or not any(run.glob("model_*.pt")):
        raise ValueError(f"{run}: no kept run with a model_*.pt")
    return checkpoints(run)[-1][1]


def evaluate_missing(run: Path) -> dict[tuple[str, str, str], dict]:
    """Every (kind, category, mode) cell of the run's student not yet in its cells file."""
    checkpoint = student(run)
    collision = f"collision={run_config(checkpoint).collision.source}"
    return evaluate_grid(checkpoint, run / CELLS, EPISODES, VALIDATION_SEED, modes=tuple(MARKS),
                         extra=[collision], split="train")  # fmt: skip


def verdict(run: Path, cells: dict[tuple[str, str, str], dict]) -> bool:
    """Print the run's table; whether every group meets its modes' marks."""
    print(f"\n### {run}\n\n| group | " + " | ".join(f"{m} [95 %]" for m in MARKS) + " |")
    print("|---|" + "---:|" * len(MARKS))
    passed = True
    for kind in BASE_KINDS:
        for category in CATEGORIES:
            row = []
            for mode, mark in MARKS.items():
                r = cells[kind, category, mode]
                wins = round(r["success"] * r["episodes"])
                low, high = wilson(wins, r["episodes"])
                short = r["success"] < mark
                passed &= not short
                row.append(f"{r['success']:.2f} [{low:.2f}, {high:.2f}]{' ✗' if short else ''}")
            print(f"| {group_name(category, kind)} | " + " | ".join(row) + " |")
    return passed


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, metavar="RUN", help="a kept run's folder")
    args = parser.parse_args(argv)
    try:
        for run in args.runs:
            student(run)
    except ValueError as err:
        print(f"validation_rule.py: {err}", file=sys.stderr)
        return 2
    results = [verdict(run, evaluate_missing(run)) for run in args.runs]
    marks = ", ".join(f"{m} >= {v:g}" for m, v in MARKS.items())
    adopted = "yes" if all(results) else "no"
    print(f"\nadopted: {adopted} ({sum(results)} of {len(results)} runs pass: {marks})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
