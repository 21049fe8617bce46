"""Evaluate a checkpoint on the held-out parts over kind x category x resistance mode.

    python experiments/generalist/evaluate.py CHECKPOINT NAME [OVERRIDES...] [--episodes 50] \
        [--seed 1000] [--modes smooth normal high] [--kinds drawer door flap]

Every cell is evaluated with the eval defaults (collision=coacd: the faithful geometry, whatever
the checkpoint was trained on) unless OVERRIDES say otherwise (e.g. collision=hull).

Appends one JSON line per cell to experiments/generalist/results/NAME/cells.jsonl (cells
already there are skipped, so an interrupted grid continues); `report.py` makes the tables
from them.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from realikea.eval.library_grid import KINDS, evaluate_grid
from realikea.sim.resistance import MODES

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("checkpoint", type=Path)
    parser.add_argument("name", help="results folder under experiments/generalist/results/")
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--seed", type=int, default=1000, help="env.seed of the draw")
    parser.add_argument("--modes", nargs="+", choices=MODES, default=list(MODES),
                        help="resistance modes to evaluate (default: all three)")  # fmt: skip
    parser.add_argument("--kinds", nargs="+", choices=KINDS, default=list(KINDS),
                        help="base kinds to evaluate (default: all three)")  # fmt: skip
    parser.add_argument("overrides", nargs="*", help="realikea eval overrides for every cell")
    args = parser.parse_args()
    evaluate_grid(
        args.checkpoint, RESULTS / args.name / "cells.jsonl", args.episodes, args.seed,
        kinds=args.kinds, modes=args.modes, extra=args.overrides,
    )  # fmt: skip


if __name__ == "__main__":
    main()
