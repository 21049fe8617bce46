"""A training run's learning curve from its metrics.csv: outcome fractions, opening, reward,
and (runs over several categories or kinds) success per category x kind, averaged over 25
iterations."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from realikea.training.metrics import read_metrics  # noqa: E402

GROUP_WINDOW = 25  # iterations averaged in the per-group panel


def plot_learning_curve(run_dir: Path, out: Path | None = None) -> Path:
    """Plot RUN_DIR/metrics.csv to `out` (default RUN_DIR/learning_curve.png); return the path."""
    series = read_metrics(run_dir)
    groups = sorted(tag for tag in series if tag.startswith("/success/"))
    draws = sorted(tag for tag in series if tag.startswith("/draw/"))  # asset.follow_success
    panels = 3 + bool(groups) + bool(draws)
    fig, axes = plt.subplots(1, panels, figsize=(5 * panels, 4))
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
        window = min(GROUP_WINDOW, len(values))
        smooth = np.convolve(values, np.ones(window) / window, mode="valid")
        axes[3].plot(its[window - 1 :], smooth, label=tag.removeprefix("/success/"))
    if groups:
        axes[3].set(
            title=f"success per category x kind ({GROUP_WINDOW}-iteration mean)",
            xlabel="iteration",
            ylim=(0, 1),
        )
        axes[3].legend(fontsize=7)
    for tag in draws:  # in the order (and so the colours) of the success panel
        its, values = series[tag]
        axes[-1].plot(its, values, label=tag.removeprefix("/draw/"))
    if draws:
        axes[-1].set(title="envs per category x kind (the draw)", xlabel="iteration")
        axes[-1].legend(fontsize=7)
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.tight_layout()
    out = out or run_dir / "learning_curve.png"
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out
