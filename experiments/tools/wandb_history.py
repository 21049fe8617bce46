"""What an offline wandb run holds: for each tag, how many steps and which (a training run logs
one row per iteration at step = iteration; realikea/training/log_writer.py).

python experiments/tools/wandb_history.py RUN_DIR [TAG ...]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from realikea.training.wandb_file import run_file, wandb_history


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", type=Path, help="a training run's folder (holds wandb/)")
    parser.add_argument("tags", nargs="*", help="only these tags (default: every tag)")
    args = parser.parse_args()
    path = run_file(args.run_dir)
    history = wandb_history(path)
    print(f"{path}: {len(history)} tags")
    for tag in args.tags or sorted(history):
        steps = sorted(history.get(tag, {}))
        span = f"steps {steps[0]}..{steps[-1]}" if steps else "no steps"
        print(f"{tag}: {len(steps)} values, {span}")


if __name__ == "__main__":
    main()
