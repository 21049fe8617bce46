"""The report's figures: success, outcomes and strategies per cell, and the learning curves."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

from realikea.runs.curves import SUCCESS_WINDOW, trailing_mean
from realikea.tasks.outcome import OUTCOMES

from .cells import STRATEGY_LABELS

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SEED_STYLES = ("-", "--", ":", "-.")
OUTCOME_COLOURS = {"fail": "tab:red", "partial": "tab:orange", "success": "tab:green"}
STRATEGY_COLOURS = dict(
    zip(
        STRATEGY_LABELS,
        ("tab:blue", "tab:purple", "tab:olive", "tab:cyan", "tab:pink", "0.75"),
        strict=True,
    )
)


def _save(fig, path: Path) -> None:
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_success(cells, variants, resistances, categories, modes, path: Path) -> None:
    """Grouped bars per category: x = (trained on, evaluated under), one bar per variant."""
    fig, axes = plt.subplots(len(categories), 1, figsize=(11, 2.8 * len(categories)), squeeze=False)
    groups = [(r, m) for r in resistances for m in modes]
    width = 0.8 / len(variants)
    for ax, category in zip(axes[:, 0], categories, strict=True):
        for i, v in enumerate(variants):
            heights = [
                cells.get((v, r, category), {}).get(m, {}).get("success", np.nan) for r, m in groups
            ]
            ax.bar(
                np.arange(len(groups)) + (i - (len(variants) - 1) / 2) * width,
                heights,
                width,
                label=v,
            )
        ax.set_xticks(np.arange(len(groups)), [f"{r}\n→ {m}" for r, m in groups], fontsize=8)
        ax.set(ylim=(0, 1.02), ylabel="success", title=category)
        ax.grid(axis="y", alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    axes[-1, 0].set_xlabel("trained on → evaluated under")
    _save(fig, path)


def plot_outcomes(cells, variants, resistances, categories, modes, path: Path) -> None:
    """Stacked Fail / Partial / Success bars per cell and evaluation mode."""
    fig, axes = plt.subplots(len(categories), 1, figsize=(11, 2.8 * len(categories)), squeeze=False)
    columns = [(v, r, m) for v in variants for r in resistances for m in modes]
    for ax, category in zip(axes[:, 0], categories, strict=True):
        bottom = np.zeros(len(columns))
        for o in OUTCOMES:
            heights = np.array(
                [cells.get((v, r, category), {}).get(m, {}).get(o, np.nan) for v, r, m in columns]
            )
            ax.bar(
                np.arange(len(columns)),
                heights,
                0.8,
                bottom=bottom,
                color=OUTCOME_COLOURS[o],
                label=o,
            )
            bottom = bottom + np.nan_to_num(heights)
        ax.set_xticks(np.arange(len(columns)), [f"{v}\n{r}→{m}" for v, r, m in columns], fontsize=6)
        ax.set(ylim=(0, 1.02), ylabel="fraction", title=category)
    axes[0, 0].legend(fontsize=8, loc="upper right")
    _save(fig, path)


def plot_strategies(totals, variants, categories, path: Path) -> None:
    """Stacked strategy fractions: one bar per collision source, a panel per category + all."""
    panels = [c for c in [*categories, "all"] if any((v, c) in totals for v in variants)]
    fig, axes = plt.subplots(
        1,
        len(panels),
        figsize=(1.1 * len(variants) * len(panels) + 1, 4.0),
        squeeze=False,
        sharey=True,
    )
    for ax, category in zip(axes[0], panels, strict=True):
        bottom = np.zeros(len(variants))
        for s, colour in STRATEGY_COLOURS.items():
            heights = np.array([totals.get((v, category), {}).get(s, 0.0) for v in variants])
            ax.bar(np.arange(len(variants)), heights, 0.7, bottom=bottom, color=colour, label=s)
            bottom += heights
        labels = [v.replace(" (", "\n(").replace(", ", ",\n") for v in variants]
        ax.set_xticks(np.arange(len(variants)), labels, fontsize=7)
        ax.set(ylim=(0, 1.02), title=category)
    axes[0, 0].set_ylabel("fraction of episodes")
    axes[0, -1].legend(fontsize=8, loc="upper right")
    _save(fig, path)


def plot_learning_curves(by_cell, variants, resistances, categories, path: Path) -> None:
    """Training success fraction against iteration, averaged over the `window` iterations of
    `iterations_to_success` (raw per-iteration values swing 0 to 1): a panel per (category,
    training resistance), a colour per collision source, a line style per seed."""
    fig, axes = plt.subplots(
        len(categories), len(resistances),
        figsize=(max(6, 4 * len(resistances)), 2.8 * len(categories)),
        squeeze=False, sharey=True,
    )  # fmt: skip
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for row, category in enumerate(categories):
        for col, res in enumerate(resistances):
            ax = axes[row, col]
            for i, v in enumerate(variants):
                for k, run in enumerate(sorted(by_cell.get((v, res, category), []), key=_seed)):
                    its, values = run["metrics"].get("/episode/success", ([], []))
                    its, values = trailing_mean(its, values, SUCCESS_WINDOW)
                    style = SEED_STYLES[k % len(SEED_STYLES)]
                    ax.plot(
                        its, values, color=colours[i % len(colours)], ls=style, lw=1.0,
                        label=f"{v}, s{run['seed']}",
                    )  # fmt: skip
            ax.set(title=f"{category}, trained on {res}", ylim=(-0.02, 1.02))
            ax.grid(alpha=0.3)
            if row == len(categories) - 1:
                ax.set_xlabel("iteration")
            if col == 0:
                ax.set_ylabel("training success")
    legend = {}  # label -> line, over every panel: each source and seed once
    for ax in axes.flat:
        handles, labels = ax.get_legend_handles_labels()
        legend.update(zip(labels, handles, strict=True))
    axes[0, -1].legend(
        legend.values(), legend.keys(), fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1)
    )
    _save(fig, path)


def _seed(run: dict) -> int:
    return run["seed"]
