"""Keep what a finished generalist run needs to be evaluated and read: its last checkpoint
(slimmed to the actor: realikea.policies.checkpoint.slim_checkpoint), its metrics.csv and its
learning curve, in experiments/generalist/results/NAME/.

    python experiments/generalist/keep.py RUN_DIR NAME [--continues EARLIER_RUN_DIR]

A run resumed from another (`train.resume=`) logs from the checkpoint it resumed; `--continues`
puts the earlier run's metrics in front, each iteration the two share taken from the resumed
run (`realikea.training.metrics.join_launches`).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from realikea.eval.sweep import checkpoints
from realikea.files import atomic_write_text
from realikea.policies.checkpoint import slim_checkpoint
from realikea.reports.learning_curve import plot_learning_curve
from realikea.training.metrics import join_launches

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("name")
    parser.add_argument("--continues", type=Path, help="the run this one was resumed from")
    args = parser.parse_args()
    last = checkpoints(args.run_dir)[-1][1]
    out = RESULTS / args.name
    out.mkdir(parents=True, exist_ok=True)
    print(f"kept {slim_checkpoint(last, out / last.name)}")
    rows = (args.run_dir / "metrics.csv").read_text().splitlines()
    if args.continues:
        earlier = (args.continues / "metrics.csv").read_text().splitlines()
        rows = join_launches(earlier + rows[1:])
    atomic_write_text(out / "metrics.csv", "\n".join(rows) + "\n")
    print(f"learning curve: {plot_learning_curve(out)}")


if __name__ == "__main__":
    main()
