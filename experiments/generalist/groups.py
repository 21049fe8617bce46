"""Which category x kind groups each kept `gated` generalist learned in training:
experiments/generalist/results/groups.md.

    python experiments/generalist/groups.py

Per run (results/<recipe>/s<seed>/metrics.csv, train parts) and group: the training success
averaged over the last 25 iterations, and the last iteration of the first full 25-iteration
window whose mean reached 0.5 ("never" if none did). A training measure, not an evaluation: the
test parts are `evaluate.py`'s.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from train_gated import RECIPES  # this folder's: the recipes it trains

from realikea.assets.catalog import CATEGORIES
from realikea.eval.library_grid import KINDS
from realikea.files import atomic_write_text
from realikea.reports.learning_curve import GROUP_WINDOW
from realikea.training.metrics import read_metrics, running_mean

RESULTS = Path(__file__).resolve().parent / "results"
LEARNED = 0.5  # the reward screen's mark of a run that learned


def group_row(run: Path) -> list[str]:
    """One cell per group: 'final mean (first iteration at LEARNED)'."""
    series = read_metrics(run)
    cells = []
    for kind in KINDS:
        for category in CATEGORIES:
            its, values = series.get(f"/success/{category}_{kind}", ([], []))
            if not values:
                cells.append("–")
                continue
            mean = running_mean(values, GROUP_WINDOW)
            # full windows only (running_mean averages fewer at the start)
            full = range(GROUP_WINDOW - 1, len(mean))
            first = next((its[i] for i in full if mean[i] >= LEARNED), None)
            cells.append(f"{mean[-1]:.2f} ({'never' if first is None else first})")
    return cells


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    groups = [f"{c} {k}" for k in KINDS for c in CATEGORIES]
    lines = [
        "# Training success per category × kind of the `gated` generalists and door specialists",
        "",
        f"`python experiments/generalist/groups.py`: train parts; per group the mean over the "
        f"last {GROUP_WINDOW} iterations and, in brackets, the first iteration at which the "
        f"{GROUP_WINDOW}-iteration mean reached {LEARNED} (full windows only).",
        "",
        "| run | " + " | ".join(groups) + " |",
        "|---|" + "---|" * len(groups),
    ]
    for recipe in RECIPES:
        for run in sorted((RESULTS / recipe).glob("s[0-9]*")):
            if (run / "metrics.csv").is_file():
                lines.append(f"| {recipe} {run.name} | " + " | ".join(group_row(run)) + " |")
    atomic_write_text(RESULTS / "groups.md", "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
