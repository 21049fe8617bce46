"""Learning curve of a training run from its metrics.csv: outcome fractions, opening, reward.

python experiments/plot_learning_curve.py RUN_DIR [--out FILE]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from realikea.reports.metrics import read_metrics  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("--out", type=Path, help="PNG (default: RUN_DIR/learning_curve.png)")
    args = parser.parse_args()
    series = read_metrics(args.run_dir)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    for name, colour in (("success", "tab:green"), ("partial", "tab:orange"), ("fail", "tab:red")):
        its, values = series.get(f"/episode/{name}", ([], []))
        axes[0].plot(its, values, color=colour, label=name)
    axes[0].set(title="episode outcome (fraction per iteration)", xlabel="iteration", ylim=(0, 1))
    axes[0].legend()
    its, values = series.get("/episode/opening", ([], []))
    axes[1].plot(its, values)
    axes[1].set(title="final opening (m or rad)", xlabel="iteration")
    its, values = series.get("Train/mean_reward", ([], []))
    axes[2].plot(its, values)
    axes[2].set(title="mean episode return", xlabel="iteration")
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    out = args.out or args.run_dir / "learning_curve.png"
    fig.savefig(out, dpi=100)
    print(f"learning curve: {out}")


if __name__ == "__main__":
    main()
