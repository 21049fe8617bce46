"""The grid v2 pilot's table: for each run (kept, parked or still in outputs/), whether and when
it learned (the first full 20-iteration window of training success at or above 0.5), its
training success over its last 30 iterations, its end stages there, how far it got and its
wall time. Writes experiments/fidelity_ablation/results/grid_v2/pilot.md.

    python experiments/fidelity_ablation/pilot_report.py
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from pilot import (
    KEPT,
    LEARNED,
    LEARNED_WINDOW,
    PARKED,
    SWITCH,
    WORK,
    first_full_window,
    series,
)

from realikea.files import atomic_write_text
from realikea.training.metrics import read_metrics

OUT = KEPT.parent / "pilot.md"
LAST = 30  # iterations the end-of-run columns average


def row(run_dir: Path, where: str) -> str:
    metrics = read_metrics(run_dir)
    its, success = series(metrics, "/episode/success")
    if not len(its):  # no episode has ended yet
        return f"| {run_dir.name} | {where} | - | never | never | - | - | - |"
    learned = first_full_window(its, success)
    randomized = first_full_window(its, success, SWITCH)
    stages = {
        tag.rsplit("/", 1)[1]: float(series(metrics, tag)[1][-LAST:].mean())
        for tag in metrics
        if tag.startswith("/end_stage/")
    }
    shown = ", ".join(f"{k}: {v:.2f}" for k, v in sorted(stages.items(), key=lambda kv: -kv[1]))
    wall = run_dir / "wall.json"  # kept or parked; in outputs/ beside the run's folder
    wall = wall if wall.is_file() else run_dir.with_name(f"{run_dir.name}.wall.json")
    seconds = json.loads(wall.read_text()) if wall.is_file() else []
    if isinstance(seconds, dict):  # a kept run's wall.json
        seconds = seconds["launches_seconds"]
    minutes = f"{sum(seconds) / 60:.0f}" if seconds else "-"
    return (
        f"| {run_dir.name} | {where} | {int(its.max()) + 1} | "
        f"{learned if learned is not None else 'never'} | "
        f"{randomized if randomized is not None else 'never'} | "
        f"{success[-LAST:].mean():.2f} | {shown} | {minutes} |"
    )


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    found = [(d, "kept") for d in sorted(KEPT.glob("*")) if d.is_dir()]
    found += [(d, "parked") for d in sorted(PARKED.glob("*")) if d.is_dir()]
    named = {d.name for d, _ in found}
    found += [(d, "training") for d in sorted(WORK.glob("*")) if d.is_dir() and d.name not in named]
    lines = [
        "# Grid v2 pilot: today's recipe under today's placements",
        "",
        "Command: `python experiments/fidelity_ablation/pilot_report.py` (runs of "
        "`python experiments/fidelity_ablation/pilot.py`; drawers, kitchen, train parts).",
        f"Learned: the first full {LEARNED_WINDOW}-iteration window of training success "
        f">= {LEARNED}, from any iteration and from the switch to randomized poses ({SWITCH}); "
        f"the last columns average the last {LAST} logged iterations. A run stops once it has "
        "learned on randomized poses; a run still training or parked is shown as far as it got. "
        "A name ending in `_none` is a placement check: the screen's placement "
        "(`scene.robot.placements=[]`, the arm 0.80 m below every handle) instead of today's.",
        "",
        "| run | state | iterations | learned at | on randomized poses at | success, last 30 "
        "| end stages, last 30 | minutes |",
        "|---|---|---:|---:|---:|---:|---|---:|",
        *(row(d, where) for d, where in found if (d / "metrics.csv").is_file()),
    ]
    atomic_write_text(OUT, "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
