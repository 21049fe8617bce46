"""Tags of a training run's metrics.csv as a table of full-window means, one row per window
(`realikea.training.metrics.window_means`): how a group's training success or a loss moved
over the run, on the same 25-iteration windows the screen's rule reads its last one on.

    python experiments/tools/windows.py RUN_DIR TAG [TAG ...] [--window 25]

e.g. `... RUN_DIR /pad_enters_success/finger_pull_door Loss/behavior`. A window's value is the
mean of its iterations that logged the tag ("–": none did); a partial last window is left out.
Exit 2, before reading further, on a run without metrics.csv or a tag it never logged.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from realikea.training.metrics import WINDOW, logged_iterations, read_metrics, window_means


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", type=Path, metavar="RUN_DIR")
    parser.add_argument("tags", nargs="+", metavar="TAG")
    parser.add_argument("--window", type=int, default=WINDOW, help="iterations a window")
    args = parser.parse_args(argv)
    if args.window < 1:
        print(f"windows.py: --window {args.window} is not a positive count", file=sys.stderr)
        return 2
    if not (args.run / "metrics.csv").is_file():
        print(f"windows.py: no metrics.csv in {args.run}", file=sys.stderr)
        return 2
    metrics = read_metrics(args.run)
    unknown = [tag for tag in args.tags if tag not in metrics]
    if unknown:
        print(f"windows.py: {args.run} never logged {', '.join(unknown)}", file=sys.stderr)
        return 2
    iterations = logged_iterations(metrics)
    columns = [window_means(*metrics[tag], iterations, args.window) for tag in args.tags]
    print(f"{args.run}: {iterations} iterations, {len(columns[0])} full windows of {args.window}")
    print("| iterations | " + " | ".join(args.tags) + " |")
    print("|---|" + "---:|" * len(args.tags))
    for k, row in enumerate(zip(*columns, strict=True)):
        shown = ["–" if v is None else f"{v:.3f}" for v in row]
        start = k * args.window
        print(f"| {start}–{start + args.window - 1} | " + " | ".join(shown) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
