"""Two kept runs' cells side by side: each cell's two successes and their difference with
Newcombe's 95 % interval, and the mean difference over the cells both runs have (a describing
figure, not a test: the policy is the unit across seeds).

    python experiments/generalist/compare_cells.py RUN_A RUN_B [--validation]

RUN is a kept run folder: its test-draw cells (cells.jsonl), or with `--validation` its
validation-draw cells (validation_cells.jsonl, what a screen run keeps). Both files are checked
before anything is printed. Exit 0, or 2 on bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cell_tables import difference_markdown

from realikea.eval.library_grid import cell_count, read_cells


def mean_difference(cells: dict, other: dict) -> tuple[float, int]:
    """The mean of (success A − success B) over the cells both grids have, and their number."""

    def rate(record: dict) -> float:
        k, n = cell_count(record)
        return k / n

    shared = sorted(set(cells) & set(other))
    differences = [rate(cells[c]) - rate(other[c]) for c in shared]
    return (sum(differences) / len(shared) if shared else 0.0), len(shared)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", type=Path, nargs=2, help="RUN_A RUN_B")
    parser.add_argument("--validation", action="store_true", help="validation_cells.jsonl")
    args = parser.parse_args(argv)
    name = "validation_cells.jsonl" if args.validation else "cells.jsonl"
    files = [run / name for run in args.runs]
    missing = [str(f) for f in files if not f.is_file()]
    if missing:
        parser.error(f"no cells: {', '.join(missing)}")
    cells, other = (read_cells(f) for f in files)
    names = tuple(str(run) for run in args.runs)
    print(difference_markdown(cells, other, names))
    mean, count = mean_difference(cells, other)
    print(f"mean difference A − B over the {count} cells both have: {mean:+.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
