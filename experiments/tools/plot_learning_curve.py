"""Learning curve of a training run from its metrics.csv
(realikea.reports.learning_curve.plot_learning_curve).

python experiments/tools/plot_learning_curve.py RUN_DIR [--out FILE]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from realikea.reports.learning_curve import plot_learning_curve


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("--out", type=Path, help="PNG (default: RUN_DIR/learning_curve.png)")
    args = parser.parse_args()
    if not (args.run_dir / "metrics.csv").is_file():
        parser.error(f"{args.run_dir} has no metrics.csv")
    print(f"learning curve: {plot_learning_curve(args.run_dir, args.out)}")


if __name__ == "__main__":
    main()
