"""The fidelity grid v2's tables and its registered comparisons, from the kept runs.

    python experiments/fidelity_ablation/grid_v2_report.py

Reads results/grid_v2/<collision>_<resistance>_<category>_s<seed>/ (eval.json on CoACD, a hull
run's eval_hull.json on its own hull, metrics.csv) and results/grid_v2/phase_map/cells.jsonl
(grid_v2_eval.py). Writes beside them runs.csv (one row a run), comparisons.json (the four
registered comparisons, Holm-corrected, then the registered sensitivity analysis without dead
runs: grid_v2_comparisons.py) and report.md (tables of both, then the frames grid_v2_frames.py
chooses).
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import sys

import numpy as np
from grid_v2 import CATEGORIES, COLLISIONS, KEPT, RESISTANCES, planned
from grid_v2_comparisons import (
    FORM_CLOSURE,
    comparison_lines,
    family,
    phase_success,
    policy_lines,
    share,
    success,
)
from grid_v2_eval import OWN, OWN_FILE, PHASE_FRICTION, PHASE_RESULTS, kept_records
from grid_v2_frames import frame_lines

from realikea.files import atomic_write_text
from realikea.reports.phase_map import read_cells
from realikea.runs.curves import iterations_to_success
from realikea.sim.resistance import MODES

LEARNED = 0.5  # a full 20-iteration window of training success at or above it
SHARES = ("hook", "lever", "pinch", "front_hook", "front_pinch")  # of the successes


def load_runs() -> list[dict]:
    """The kept runs with their evaluations by geometry, phase-map cells and learned iteration."""
    runs = kept_records(KEPT)
    cells = read_cells(PHASE_RESULTS)
    for run in runs:
        run["name"] = run["dir"].name
        run["evals"] = {"coacd": run["eval"]}
        if (run["dir"] / OWN_FILE).is_file():
            run["evals"][OWN] = json.loads((run["dir"] / OWN_FILE).read_text())
        run["learned_at"] = iterations_to_success(run, LEARNED)
        run["wall_minutes"] = wall_minutes(run["dir"])
        run["phase"] = {
            force: cell["success"]
            for (label, _, _, force, mu), cell in cells.items()
            if label == run["name"] and mu == PHASE_FRICTION
        }
    return runs


def wall_minutes(run_dir) -> float | None:
    """The wall time of a kept run's launches (training and its evaluation), in minutes."""
    path = run_dir / "wall.json"
    if not path.is_file():
        return None
    return sum(json.loads(path.read_text())["launches_seconds"]) / 60


def compute_line(runs: list[dict]) -> str:
    timed = [r["wall_minutes"] for r in runs if r["wall_minutes"] is not None]
    return (
        f"Compute: {sum(timed) / 60:.1f} h of wall time over the launches of {len(timed)} kept "
        "runs (training and the evaluation after it; two runs at a time on 2 cores, one env "
        "worker each), evaluations by `grid_v2_eval.py` not counted."
    )


def runs_csv(runs: list[dict]) -> str:
    """One row a run: cell, learned iteration, success per geometry and mode, shares in high."""
    fields = ["name", "collision", "resistance", "category", "seed", "iterations", "learned_at"]
    fields += ["wall_minutes"]
    fields += [f"success_{g}_{m}" for g in ("coacd", OWN) for m in MODES]
    fields += [f"share_{label}_high" for label in SHARES] + ["phase_success"]
    out = io.StringIO()
    writer = csv.DictWriter(out, fields, lineterminator="\n")
    writer.writeheader()
    for run in runs:
        row = {f: run.get(f) for f in fields[:6]} | {"learned_at": run["learned_at"]}
        row["wall_minutes"] = None if run["wall_minutes"] is None else f"{run['wall_minutes']:.1f}"
        for geometry, report in run["evals"].items():
            if geometry == "coacd" or run["collision"] == geometry:
                row |= {f"success_{geometry}_{m}": report["modes"][m]["success"] for m in MODES}
        row |= {f"share_{label}_high": share(run, (label,)) for label in SHARES}
        writer.writerow(row | {"phase_success": phase_success(run)})
    return out.getvalue()


def _mean(values) -> str:
    return "–" if not values else f"{np.mean(values):.2f}"


def cell_lines(runs: list[dict]) -> list[str]:
    """Per cell and source: runs kept of planned, learned, mean success on CoACD and own hull."""
    lines = [
        "| category | trained in | source | kept / planned | learned | CoACD smooth | normal "
        "| high | own hull high | hook share | form closure share |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    plan = planned()
    for category in CATEGORIES:
        for resistance in RESISTANCES:
            for collision in COLLISIONS:
                key = (collision, resistance, category)
                cell = [r for r in runs if (r["collision"], r["resistance"], r["category"]) == key]
                n = sum((p.collision, p.resistance, p.category) == key for p in plan)
                learned = sum(r["learned_at"] is not None for r in cell)
                own = [success(r, OWN) for r in cell if OWN in r["evals"] and collision == OWN]
                lines.append(
                    f"| {category} | {resistance} | {collision} | {len(cell)} / {n} | {learned} | "
                    + " | ".join(_mean([success(r, "coacd", m) for r in cell]) for m in MODES)
                    + f" | {_mean(own)} | {_mean([share(r, ('hook',)) for r in cell])} | "
                    f"{_mean([share(r, FORM_CLOSURE) for r in cell])} |"
                )
    return lines


def main(argv: list[str] | None = None) -> int:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    runs = load_runs()
    learned = [r for r in runs if r["learned_at"] is not None]
    results = {"registered": family(runs), "sensitivity_learned_only": family(learned)}
    atomic_write_text(KEPT / "runs.csv", runs_csv(runs))
    atomic_write_text(KEPT / "comparisons.json", json.dumps(results, indent=2) + "\n")
    lines = [
        "# Fidelity grid v2: cells and registered comparisons",
        "",
        "Command: `python experiments/fidelity_ablation/grid_v2_report.py` (data: `runs.csv`, "
        "`comparisons.json`). Drawers, kitchen, trained on train parts, seeds 100-104 / "
        "100-102; every policy's last checkpoint evaluated on the test parts, randomized poses, "
        "draw 1000, 50 episodes a mode, Franka Hand, elliptic cones. Learned: a full 20-iteration "
        f"window of training success >= {LEARNED}. Shares are of the successes in high on CoACD "
        "(a policy with none counts 0).",
        "",
        f"{len(runs)} of {len(planned())} planned runs kept; {len(learned)} learned.",
        "",
        compute_line(runs),
        "",
        *cell_lines(runs),
        "",
        "## Registered comparisons (Holm over the four; exact permutation test over seeds)",
        "",
        *comparison_lines(results["registered"]),
        "",
        "## Sensitivity analysis (registered): only the runs that learned",
        "",
        *comparison_lines(results["sensitivity_learned_only"]),
        "",
        "## Each policy's value in the registered comparisons, with its episodes",
        "",
        *policy_lines(runs),
        "",
        *frame_lines(runs),
    ]
    atomic_write_text(KEPT / "report.md", "\n".join(lines))
    print(f"report: {KEPT / 'report.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
