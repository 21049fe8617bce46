"""Keep what a finished generalist run needs to be evaluated and read: its last checkpoint
(slimmed to the actor: realikea.policies.checkpoint.slim_checkpoint), its metrics.csv and its
learning curve, in experiments/generalist/NAME/.

    python experiments/generalist/keep.py RUN_DIR NAME
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
from pathlib import Path

from realikea.policies.checkpoint import slim_checkpoint

HERE = Path(__file__).resolve().parent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("name")
    args = parser.parse_args()
    last = max(args.run_dir.glob("model_*.pt"), key=lambda p: int(p.stem.split("_")[1]))
    out = HERE / args.name
    out.mkdir(parents=True, exist_ok=True)
    print(f"kept {slim_checkpoint(last, out / last.name)}")
    shutil.copy(args.run_dir / "metrics.csv", out / "metrics.csv")
    plot = HERE.parent / "plot_learning_curve.py"
    curve = out / "learning_curve.png"
    subprocess.run([sys.executable, str(plot), str(args.run_dir), "--out", str(curve)], check=True)


if __name__ == "__main__":
    main()
