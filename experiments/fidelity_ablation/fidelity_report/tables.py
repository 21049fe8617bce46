"""Markdown tables of the cells and runs: outcomes, intervals, differences, strategies, compute."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from realikea.markdown import table
from realikea.runs.curves import PLATEAU_WINDOW, iterations_to_success, last_windows
from realikea.runs.records import train_seconds
from realikea.sim.resistance import MODES
from realikea.tasks.failure_modes import FAILURE_MODES
from realikea.tasks.outcome import OUTCOMES

from .cells import (
    FORM_CLOSURE,
    STRATEGY_LABELS,
    paired_differences,
    present_cells,
    rate_interval,
)


def _fmt(value, digits=2) -> str:
    return "–" if value is None else f"{value:.{digits}f}"


def relative(path: Path, root: Path) -> str:
    return os.path.relpath(Path(path).resolve(), Path(root).resolve())


def outcome_tables(cells: dict, variants, resistances, categories, modes) -> list[str]:
    """Fail / Partial / Success per cell and evaluation mode, mean over seeds."""
    lines = [
        "## Fail / Partial / Success per cell",
        "",
    ]
    rows = []
    for v, res, category in present_cells(cells, variants, resistances, categories):
        cell = cells[v, res, category]
        seeds = max(c["seeds"] for c in cell.values())
        values = []
        for m in modes:
            c = cell.get(m)
            values += [_fmt(c[o]) for o in OUTCOMES] if c else ["", "", ""]
        rows.append([v, res, category, str(seeds), *values])
    header = ["collision", "trained on", "category", "seeds",
              *(c for m in modes for c in (f"{m} F", "P", "S"))]  # fmt: skip
    return lines + table(header, "lllr" + "rrr" * len(modes), rows)


def interval_lines(
    cells: dict, by_cell: dict, variants, resistances, categories, modes
) -> list[str]:
    """Success per cell with its 95 % interval, the number of seeds and how many of them
    learned to open in training."""
    lines = [
        "## Success with 95 % intervals",
        "",
        "Mean success over seeds [95 % interval]: with one seed, Wilson's interval over its "
        "episodes; with several, a percentile bootstrap that redraws seeds, then each seed's "
        "episodes (`realikea.eval.stats.seed_interval`), so seed-to-seed spread counts. "
        "`learned`: the seeds whose training success reached 50 % (`to 50 %` below); a run "
        "that never finds an opening pulls its cell's mean down whatever the geometry.",
        "",
    ]
    rows = []
    for v, res, category in present_cells(cells, variants, resistances, categories):
        cell = cells[v, res, category]
        values = []
        for m in modes:
            if m not in cell:
                values.append("")
                continue
            mean, lo, hi = rate_interval(cell[m]["runs"])
            values.append(f"{mean:.2f} [{lo:.2f}, {hi:.2f}]")
        seeds = max(c["seeds"] for c in cell.values())
        learned = sum(iterations_to_success(r) is not None for r in by_cell[v, res, category])
        rows.append([v, res, category, str(seeds), str(learned), *values])
    header = ["collision", "trained on", "category", "seeds", "learned", *modes]
    return lines + table(header, "lllrr" + "l" * len(modes), rows)


def difference_lines(
    cells: dict, variants, resistances, categories, modes, measure: str = "success"
) -> list[str]:
    """CoACD minus hull of `measure` (`paired_differences`), with its interval and whether it
    is significant (uncorrected): Newcombe's interval with one seed a side, the permutation test
    over seeds with several (`Difference.significant`)."""
    title = "CoACD − hull" if measure == "success" else f"{measure.capitalize()} rate: CoACD − hull"
    lines = [
        f"## {title}",
        "",
        f"Difference of the mean {measure} rate [95 % interval]. One seed a side: Newcombe's "
        "interval, significant where it excludes zero. Several seeds a side: the two-level "
        "bootstrap's interval (descriptive) and an exact permutation test over the seeds, the "
        "seed the unit (`realikea.eval.stats.seed_permutation_p`, p in brackets; at least 0.10 "
        "with three seeds a side), significant where p < 0.05 and the interval excludes zero. "
        "Uncorrected; the family's correction is in its section 'Every difference at once (Holm)'.",
        "",
    ]
    rows = []
    for (coacd, res, category, m), diff in paired_differences(
        cells, variants, resistances, categories, modes, measure
    ):
        d, lo, hi = diff.interval()
        verdict = "significant" if diff.significant() else "not significant"
        if diff.several:
            verdict += f" (seeds: p = {diff.p():.2f})"
        mean_a, mean_b = (np.mean([k / n for k, n in r]) for r in (diff.a, diff.b))
        rows.append([coacd, res, category, m, f"{mean_a:.2f}", f"{mean_b:.2f}",
                     f"{d:+.2f} [{lo:+.2f}, {hi:+.2f}]", verdict])  # fmt: skip
    header = ["CoACD", "trained on", "category", "evaluated in", "CoACD", "hull",
              "CoACD − hull [95 %]", "verdict"]  # fmt: skip
    return lines + table(header, "llllrrll", rows)


def failure_lines(cells: dict, variants, resistances, categories, mode: str = "high") -> list[str]:
    """Failure modes per cell under one evaluation mode (fractions of all its episodes)."""
    lines = [
        f"## Failure modes (evaluated in {mode})",
        "",
        "Fraction of all episodes that failed (fail or partial) in each mode "
        "(realikea/tasks/failure_modes.py; validated in "
        "experiments/fidelity_ablation/results/failure_modes.md), mean over seeds [95 % "
        "interval, as for the success]; the means add up to 1 − success.",
        "",
    ]
    rows = []
    for v, res, category in present_cells(cells, variants, resistances, categories):
        entry = cells[v, res, category].get(mode, {})
        if "failure_runs" in entry:
            values = []
            for f in FAILURE_MODES:
                mean, lo, hi = rate_interval(entry["failure_runs"][f])
                values.append(f"{mean:.2f} [{lo:.2f}, {hi:.2f}]")
            rows.append([v, res, category, *values])
    header = ["collision", "trained on", "category", *FAILURE_MODES]
    return lines + table(header, "l" * len(header), rows)


def strategy_lines(cells, totals, variants, categories) -> list[str]:
    lines = [
        "## Strategies by collision source",
        "",
        "Fraction of evaluation episodes per classifier label (realikea/tasks/contacts.py), "
        "averaged over training resistances, evaluation modes and seeds; friction share and "
        "front share = mean share of the pull carried by friction and by contacts on the front "
        "off the part (`front_*` labels) in episodes that pulled.",
        "",
    ]

    def mean_stat(v, category, stat):
        values = [
            m[stat]
            for (cv, _, cc), modes in cells.items()
            if cv == v and category in (cc, "all")
            for m in modes.values()
            if m.get(stat) is not None
        ]
        return float(np.mean(values)) if values else None

    rows = [
        [v, category, *(_fmt(totals[v, category][s]) for s in STRATEGY_LABELS),
         _fmt(mean_stat(v, category, "friction_share")),
         _fmt(mean_stat(v, category, "front_share"))]
        for v in variants
        for category in [*categories, "all"]
        if (v, category) in totals
    ]  # fmt: skip
    header = ["collision", "category", *STRATEGY_LABELS, "friction share", "front share"]
    return lines + table(header, "ll" + "r" * (len(STRATEGY_LABELS) + 2), rows)


def per_run_lines(runs: list[dict], root: Path) -> list[str]:
    """One row per run: success under each evaluation mode, strategy fractions under its
    training resistance, and how soon training found a way to open."""
    lines = [
        "## Per run",
        "",
        "Success under each evaluation mode; strategy fractions under the run's training "
        "resistance; `form closure of S`: the share of its successful episodes there labelled "
        "`hook` or `lever`; `to 50 %`: the first iteration from which training success, "
        "averaged over the next 20 iterations, reaches 50 % (how soon the run found a way to "
        "open); `train S` and `train P`: training success and partial openings over the last "
        f"{PLATEAU_WINDOW} iterations, with their change from the {PLATEAU_WINDOW} before "
        "(a run still climbing has not plateaued).",
        "",
    ]
    rows = []
    for run in runs:
        modes = run["eval"]["modes"]
        success = [_fmt(modes[m]["success"]) if m in modes else "" for m in MODES]
        trained = modes.get(run["resistance"]) or {}
        fractions = [_fmt((trained.get("strategies") or {}).get(s)) for s in STRATEGY_LABELS]
        won = trained.get("success_strategies")
        has_wins = won and trained["success"] > 0
        closure = _fmt(sum(won[label] for label in FORM_CLOSURE)) if has_wins else "–"
        reached = iterations_to_success(run)
        row = [*success, *fractions, closure, "–" if reached is None else str(reached)]
        for tag in ("/episode/success", "/episode/partial"):
            mean, change = last_windows(run, tag)
            row += [_fmt(mean), "–" if change is None else f"{change:+.2f}"]
        rows.append([relative(run["dir"], root), *row])
    header = ["run", *(f"{m} S" for m in MODES), *STRATEGY_LABELS, "form closure of S",
              "to 50 %", "train S", "change", "train P", "change"]  # fmt: skip
    return lines + table(header, "l" + "r" * (len(header) - 1), rows)


def compute_lines(runs: list[dict], root: Path) -> list[str]:
    lines = [
        "## Compute",
        "",
        "Iterations behind the evaluated checkpoint; the last launch's iterations, training "
        "minutes and seconds per iteration (a resumed run's earlier launches are in its wall "
        "time only); eval minutes from eval.json; wall: every launch of the run, training and "
        "evaluation, beside whatever else ran.",
        "",
    ]
    rows, total = [], 0.0
    for run in runs:
        seconds = train_seconds(run)
        eval_seconds = run["eval"].get("eval_seconds", 0.0)
        total += sum(run["wall"]) if run["wall"] else (seconds or 0.0) + eval_seconds
        per_it = seconds / run["launch_iterations"] if seconds else None
        rows.append([
            relative(run["dir"], root), str(run["iterations"]), str(run["num_envs"]),
            str(run["launch_iterations"]), _fmt(seconds / 60 if seconds else None, 1),
            _fmt(per_it), f"{eval_seconds / 60:.1f}",
            _fmt(sum(run["wall"]) / 60 if run["wall"] else None, 1),
        ])  # fmt: skip
    header = ["run", "iterations", "envs", "last launch: its", "train (min)", "s / iteration",
              "eval (min)", "wall (min)"]  # fmt: skip
    lines += table(header, "l" + "r" * 7, rows)
    lines += ["", f"Total compute (sum over runs; wall time where recorded): {total / 3600:.2f} h."]
    return lines
