"""The fidelity grid v2's tables and its registered comparisons, from the kept runs.

    python experiments/fidelity_ablation/grid_v2_report.py

Reads results/grid_v2/<collision>_<resistance>_<category>_s<seed>/ (eval.json on CoACD, a hull
run's eval_hull.json on its own hull, metrics.csv) and results/grid_v2/phase_map/cells.jsonl
(grid_v2_eval.py). Writes beside them runs.csv (one row a run), comparisons.json (the four
registered comparisons, Holm-corrected, then the registered sensitivity analysis without dead
runs) and report.md (tables of both). The comparisons are fixed in README.md, "The grid on
today's recipe"; the seed is the unit (realikea/eval/permutation.py).
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from dataclasses import dataclass

import numpy as np
from grid_v2 import CATEGORIES, COLLISIONS, KEPT, RESISTANCES, planned
from grid_v2_eval import OWN, OWN_FILE, PHASE_FORCES, PHASE_FRICTION, PHASE_RESULTS, kept_records

from realikea.eval.permutation import shift_interval, stratified_difference
from realikea.eval.permutation import stratified_permutation_p as permutation_p
from realikea.eval.stats import holm
from realikea.files import atomic_write_text
from realikea.reports.fidelity_ablation.runs import iterations_to_success
from realikea.reports.phase_map import read_cells
from realikea.sim.resistance import MODES

LEARNED = 0.5  # a full 20-iteration window of training success at or above it
SHARES = ("hook", "lever", "pinch", "front_hook", "front_pinch")  # of the successes
FORM_CLOSURE = ("hook", "lever")


def success(run: dict, geometry: str = "coacd", mode: str = "high") -> float:
    return run["evals"][geometry]["modes"][mode]["success"]


def share(run: dict, labels, mode: str = "high") -> float:
    """The share of the run's CoACD successes in `mode` labelled one of `labels` (0 with none)."""
    entry = run["evals"]["coacd"]["modes"][mode]
    return sum(entry["success_strategies"][label] for label in labels)


def phase_success(run: dict) -> float | None:
    """Success over the hard-pad phase-map cells of the run (None until all are mapped)."""
    found = [run["phase"].get(force) for force in PHASE_FORCES]
    return None if None in found else float(np.mean(found))


@dataclass(frozen=True)
class Comparison:
    """A registered CoACD - hull comparison: its cells (strata) and each policy's value."""

    label: str
    cells: tuple[tuple[str, str], ...]  # (category, training resistance) per stratum
    value: object  # run -> float (None: not yet evaluated)


REGISTERED = (
    Comparison("1. two-point x high: hook share of successes", (("two_point", "high"),),
               lambda r: share(r, ("hook",))),
    Comparison("2. knob x high: form-closure (hook + lever) share of successes",
               (("knob", "high"),), lambda r: share(r, FORM_CLOSURE)),
    Comparison("3. trained in smooth, evaluated in high: success (stratified by category)",
               tuple((c, "smooth") for c in CATEGORIES), success),
    Comparison(f"4. hard-pad phase map (mu {PHASE_FRICTION:g}, "
               f"{'/'.join(f'{f:g}' for f in PHASE_FORCES)} N): two-point x high success",
               (("two_point", "high"),), phase_success),
)  # fmt: skip


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


def compare(comparison: Comparison, runs: list[dict]) -> dict:
    """The comparison's per-policy values, difference, shift interval and exact p."""
    strata, missing = [], 0
    for category, resistance in comparison.cells:
        sides = []
        for collision in COLLISIONS:
            chosen = [r for r in runs if (r["collision"], r["category"], r["resistance"])
                      == (collision, category, resistance)]  # fmt: skip
            values = [comparison.value(r) for r in chosen]
            missing += values.count(None)
            sides.append([v for v in values if v is not None])
        strata.append(sides)
    out = {"comparison": comparison.label, "strata": [list(c) for c in comparison.cells],
           "values": strata, "unevaluated": missing}  # fmt: skip
    if any(not a or not b for a, b in strata):
        return {**out, "difference": None}
    low, high = (None if math.isinf(end) else end for end in shift_interval(strata))
    return {**out, "difference": stratified_difference(strata), "low": low, "high": high,
            "p": permutation_p(strata)}  # fmt: skip


def family(runs: list[dict]) -> list[dict]:
    """The registered comparisons on `runs`, Holm-corrected over all four: one not computable
    yet (a side without policies) counts as p = 1, so a partial grid is never corrected less."""
    results = [compare(c, runs) for c in REGISTERED]
    adjusted = holm([r.get("p", 1.0) for r in results])
    for result, p_holm in zip(results, adjusted, strict=True):
        if result["difference"] is not None:
            result["p_holm"] = p_holm
            result["significant"] = bool(p_holm < 0.05)
    return results


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


def _end(value: float | None, unbounded: str) -> str:
    return unbounded if value is None else f"{value:+.2f}"


def comparison_lines(results: list[dict]) -> list[str]:
    """A row a comparison; an interval end that no shift in reach bounds (three policies a
    side cannot reject any) shows as infinite."""
    lines = [
        "| comparison | CoACD / hull policies | CoACD − hull [95 %] | p | Holm p | verdict |",
        "|---|---|---|---:|---:|---|",
    ]
    for r in results:
        sizes = " + ".join(f"{len(a)} / {len(b)}" for a, b in r["values"])
        if r["unevaluated"]:
            sizes += f" ({r['unevaluated']} kept, not yet evaluated)"
        if r["difference"] is None:
            lines.append(f"| {r['comparison']} | {sizes} | not computable yet | | | |")
            continue
        verdict = "significant" if r["significant"] else "not significant"
        lines.append(
            f"| {r['comparison']} | {sizes} | {r['difference']:+.2f} "
            f"[{_end(r['low'], '−∞')}, {_end(r['high'], '∞')}] | {r['p']:.4f} | "
            f"{r['p_holm']:.4f} | {verdict} |"
        )
    return lines


def main() -> int:
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
    ]
    atomic_write_text(KEPT / "report.md", "\n".join(lines))
    print(f"report: {KEPT / 'report.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
