"""Learning curve of a training run from its metrics.csv: outcome fractions, opening, reward,
and (runs over several categories or kinds) success per category x kind, averaged over 25
iterations.

python experiments/tools/plot_learning_curve.py RUN_DIR [--out FILE]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from realikea.training.metrics import read_metrics  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("--out", type=Path, help="PNG (default: RUN_DIR/learning_curve.png)")
    args = parser.parse_args()
    series = read_metrics(args.run_dir)
    groups = sorted(tag for tag in series if tag.startswith("/success/"))
    fig, axes = plt.subplots(1, 4 if groups else 3, figsize=(20 if groups else 15, 4))
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
    for tag in groups:
        its, values = series[tag]
        window = min(25, len(values))
        smooth = np.convolve(values, np.ones(window) / window, mode="valid")
        axes[3].plot(its[window - 1 :], smooth, label=tag.removeprefix("/success/"))
    if groups:
        axes[3].set(
            title="success per category x kind (25-iteration mean)", xlabel="iteration", ylim=(0, 1)
        )
        axes[3].legend(fontsize=7)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    out = args.out or args.run_dir / "learning_curve.png"
    fig.savefig(out, dpi=100)
    print(f"learning curve: {out}")


if __name__ == "__main__":
    main()
