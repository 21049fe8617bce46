"""The reward screen's table and learning curves from the kept runs (experiments/reward_screen/
runs/): per recipe, cell and collision source, how many seeds reached 50 % training success and
at which iteration, and the reward stage the others ended their episodes in.

    python experiments/reward_screen/report.py [--runs DIR] [--out DIR]

Writes OUT/table.md, OUT/figures.json (the counts the README quotes by key) and
OUT/learning_curves.png (OUT defaults to experiments/reward_screen/results).
"Learned": the training success, averaged over 20 iterations from some iteration on, reached
0.5 (`iterations_to_success`, as the fidelity grid's report counts it). End stage: the share of
episodes ending in each stage over the last 20 iterations (`/end_stage/<k>`).
"""

from __future__ import annotations

import argparse
import json
import re
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from realikea.files import WORKSPACE, atomic_write_text  # noqa: E402
from realikea.markdown import table  # noqa: E402
from realikea.runs.curves import SUCCESS_WINDOW, iterations_to_success, trailing_mean  # noqa: E402
from realikea.training.metrics import read_metrics  # noqa: E402

NAME = re.compile(r"(?P<recipe>.+)_(?P<collision>coacd|hull)_(?P<cell>.+)_s(?P<seed>\d+)$")
STAGES = (1, 2, 3, 4)


def load_runs(root: Path) -> list[dict]:
    """Every kept run under `root`: its name's parts, metrics and wall time."""
    runs = []
    for path in sorted(p for p in root.iterdir() if (p / "metrics.csv").is_file()):
        match = NAME.match(path.name)
        if not match:
            continue
        wall = json.loads((path / "wall.json").read_text())["launches_seconds"]
        runs.append({**match.groupdict(), "seed": int(match["seed"]), "path": path,
                     "metrics": read_metrics(path), "minutes": sum(wall) / 60})  # fmt: skip
    return runs


def tail_mean(run: dict, tag: str, window: int = SUCCESS_WINDOW) -> float | None:
    its, values = (np.asarray(x, float) for x in run["metrics"].get(tag, ([], [])))
    if its.size == 0:
        return None
    return float(values[its > its.max() - window].mean())


def end_stage(run: dict) -> str:
    """The stages episodes ended in over the last iterations, largest share first."""
    shares = {k: tail_mean(run, f"/end_stage/{k}") for k in STAGES}
    shares = {k: v for k, v in shares.items() if v}
    if not shares:
        return "-"
    return ", ".join(f"{k}: {v:.2f}" for k, v in sorted(shares.items(), key=lambda kv: -kv[1]))


def runs_table(runs: list[dict]) -> str:
    """One row per recipe x cell x collision source; one line per run that did not learn."""
    cells = defaultdict(list)
    for run in runs:
        cells[run["recipe"], run["cell"], run["collision"]].append(run)
    rows, stuck = [], []
    for (recipe, cell, collision), group in sorted(cells.items()):
        group.sort(key=lambda r: r["seed"])
        reached = [iterations_to_success(r) for r in group]
        learned = sum(x is not None for x in reached)
        its = ", ".join(f"s{r['seed']} {x if x is not None else 'never'}" for r, x in
                        zip(group, reached, strict=True))  # fmt: skip
        final = ", ".join(f"{tail_mean(r, '/episode/success') or 0:.2f}" for r in group)
        minutes = np.mean([r["minutes"] for r in group])
        rows.append([recipe, cell, collision, f"{learned} / {len(group)}", its, final,
                     f"{minutes:.0f}"])  # fmt: skip
        for run, x in zip(group, reached, strict=True):
            if x is None:
                opening = tail_mean(run, "/episode/opening") or 0.0
                stuck.append(f"- {run['path'].name}: end stage {end_stage(run)}; "
                             f"opening {opening:.3f}")  # fmt: skip
    header = ["recipe", "cell", "collision", "learned / run", "iteration to 50 % (each seed)",
              "training success, last 20 its (each seed)", "minutes a run"]  # fmt: skip
    lines = table(header, "lllrllr", rows)
    out = "\n".join(lines) + "\n"
    if stuck:
        out += "\nRuns that did not learn (shares of episodes by end stage, mean opening):\n\n"
        out += "\n".join(stuck) + "\n"
    return out


def figures(runs: list[dict]) -> dict:
    """Runs learned per recipe, per recipe and cell, and per recipe, cell and source, with each
    seed's iteration to 50 % (null: never)."""
    out: dict = {}
    for run in sorted(runs, key=lambda r: (r["recipe"], r["cell"], r["collision"], r["seed"])):
        reached = iterations_to_success(run)
        recipe = out.setdefault(run["recipe"], {"learned": 0, "runs": 0, "cells": {}})
        cell = recipe["cells"].setdefault(run["cell"], {"learned": 0, "runs": 0, "sources": {}})
        source = cell["sources"].setdefault(run["collision"], {"learned": 0, "runs": 0})
        source.setdefault("seeds", {})
        for counts in (recipe, cell, source):
            counts["learned"] += reached is not None
            counts["runs"] += 1
        source["seeds"][f"s{run['seed']}"] = reached
    return {"recipes": out}


# the curves: tag, axis label, y range, the line across (learned; success on a drawer)
CURVES = (
    ("/episode/success", "training success", (-0.02, 1.02), 0.5),
    ("/episode/opening", "mean opening (m)", (-0.01, 0.5), 0.20),
)


def plot(runs: list[dict], path: Path) -> None:
    """Training success and mean opening (20-iteration means) against iteration: a column per
    recipe and cell, so a run that did not learn shows how far it pulled."""
    panels = sorted({(r["recipe"], r["cell"]) for r in runs})
    cols = min(4, len(panels))
    rows = -(-len(panels) // cols)
    fig, axes = plt.subplots(len(CURVES) * rows, cols, figsize=(4 * cols, 2.6 * len(CURVES) * rows),
                             squeeze=False, sharex=True)  # fmt: skip
    colours = {"coacd": "tab:blue", "hull": "tab:orange"}
    for i, (recipe, cell) in enumerate(panels):
        for k, (tag, label, ylim, line) in enumerate(CURVES):
            ax = axes[len(CURVES) * (i // cols) + k, i % cols]
            for run in sorted(runs, key=lambda r: (r["collision"], r["seed"])):
                if (run["recipe"], run["cell"]) != (recipe, cell):
                    continue
                its, values = trailing_mean(*run["metrics"].get(tag, ([], [])), SUCCESS_WINDOW)
                ax.plot(its, values, color=colours[run["collision"]], lw=0.9, alpha=0.8,
                        label=run["collision"])  # fmt: skip
            ax.axhline(line, color="grey", lw=0.6, ls=":")
            ax.set(ylim=ylim, ylabel=label if i % cols == 0 else None)
            ax.grid(alpha=0.3)
            if k == 0:
                ax.set_title(f"{recipe}: {cell}")
            if k == len(CURVES) - 1:
                ax.set_xlabel("iteration")
    for i in range(len(panels), rows * cols):
        for k in range(len(CURVES)):
            axes[len(CURVES) * (i // cols) + k, i % cols].axis("off")
    handles = {}  # label -> line, over every panel
    for ax in axes.flat:
        lines, labels = ax.get_legend_handles_labels()
        handles.update(zip(labels, lines, strict=True))
    axes[0, 0].legend(handles.values(), handles.keys(), fontsize=8, loc="upper left")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    results = WORKSPACE / "experiments/reward_screen/results"
    parser.add_argument("--runs", type=Path, default=results / "runs")
    parser.add_argument("--out", type=Path, default=results)
    args = parser.parse_args()
    if not args.runs.is_dir():
        parser.error(f"--runs {args.runs}: no such folder (run screen.py first)")
    runs = load_runs(args.runs)
    if not runs:
        parser.error(f"--runs {args.runs}: no kept run in it")
    atomic_write_text(args.out / "table.md", runs_table(runs))
    atomic_write_text(args.out / "figures.json", json.dumps(figures(runs), indent=1) + "\n")
    plot(runs, args.out / "learning_curves.png")
    print(runs_table(runs))
    print(f"wrote {args.out / 'table.md'}, figures.json and {args.out / 'learning_curves.png'} "
          f"({len(runs)} runs, {sum(r['minutes'] for r in runs) / 60:.1f} h)")  # fmt: skip


if __name__ == "__main__":
    main()
