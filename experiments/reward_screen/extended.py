"""The screen's runs trained past 400 iterations (exploratory, not part of the screen): where each
passed 50 % training success (as `report.py` counts it: the first iteration of the window), and
its success, opening and stage-4 share over its last 20 iterations. Reads
experiments/reward_screen/results/extended/NAME/metrics.csv; prints a markdown table.

    python experiments/reward_screen/extended.py
"""

from __future__ import annotations

import argparse

from realikea.files import WORKSPACE
from realikea.runs.curves import SUCCESS_WINDOW, iterations_to_success, trailing_mean
from realikea.training.metrics import read_metrics

EXTENDED = WORKSPACE / "experiments/reward_screen/results/extended"


def main(argv: list[str] | None = None) -> int:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    print("| run | iterations | learned at | success | opening (m) | stage 4 |")
    print("|---|---|---:|---:|---:|---:|")
    for run in sorted(p for p in EXTENDED.iterdir() if (p / "metrics.csv").is_file()):
        metrics = read_metrics(run)
        first = iterations_to_success({"metrics": metrics})
        last = [
            trailing_mean(*metrics[tag], SUCCESS_WINDOW)[1][-1]
            for tag in ("/episode/success", "/episode/opening", "/end_stage/4")
        ]
        its = metrics["/episode/success"][0]
        span = f"{min(its)}-{max(its)}"
        learned = "never" if first is None else str(first)
        print(
            f"| {run.name} | {span} | {learned} | {last[0]:.2f} | {last[1]:.3f} | {last[2]:.2f} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
