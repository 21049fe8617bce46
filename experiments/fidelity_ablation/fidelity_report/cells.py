"""Runs pooled into cells per evaluation mode; their rates, intervals and CoACD − hull pairs."""

from __future__ import annotations

from collections import defaultdict

import numpy as np

from realikea.eval.stats import count, seed_interval, wilson
from realikea.eval.table import CONTACT_STATS
from realikea.reports.multiplicity import Difference
from realikea.runs.records import schedule
from realikea.sim.resistance import MODES
from realikea.tasks.failure_modes import FAILURE_MODES
from realikea.tasks.outcome import OUTCOMES

# the strategy labels (realikea/tasks/contacts.py) in the report's column order
STRATEGY_LABELS = ("pinch", "hook", "lever", "front_pinch", "front_hook", "none")
# per-episode labels an eval.json counts as rates: (its field, the labels, the cell key their
# per-seed (count, episodes) go to)
LABEL_FIELDS = (
    ("failure_modes", FAILURE_MODES, "failure_runs"),
    ("strategies", STRATEGY_LABELS, "strategy_runs"),
)
# the paper's form closure: a hook on a bar or lip, a lever on a knob (realikea/tasks/contacts.py)
FORM_CLOSURE = ("hook", "lever")


def variant(run: dict, presets: int, schedules: int = 1) -> str:
    """The collision source, with the gripper/contact preset and the training schedule when
    several are present (the paper's 1,500 iterations are not pooled with the grid's 900)."""
    tags = [f"{run['gripper']}, {run['contact']}"] if presets > 1 else []
    tags += [schedule(run)] if schedules > 1 else []
    return run["collision"] + (f" ({'; '.join(tags)})" if tags else "")


def ordered(values, order=()) -> list:
    """The distinct values: those in `order` first, in its order, then the rest sorted."""
    present = set(values)
    return [v for v in order if v in present] + sorted(present - set(order))


def aggregate(runs: list[dict]) -> tuple[dict, dict]:
    """cell (variant, resistance, category) -> eval mode -> mean summary over seeds; and
    cell -> its runs."""
    presets = len({(r["gripper"], r["contact"]) for r in runs})
    schedules = len({schedule(r) for r in runs})
    by_cell = defaultdict(list)
    for run in runs:
        run["variant"] = variant(run, presets, schedules)
        by_cell[run["variant"], run["resistance"], run["category"]].append(run)
    cells = {}
    for key, members in by_cell.items():
        modes = {}
        for mode in ordered({m for r in members for m in r["eval"]["modes"]}, MODES):
            entries = [r["eval"]["modes"][mode] for r in members if mode in r["eval"]["modes"]]
            out = {o: float(np.mean([e[o] for e in entries])) for o in OUTCOMES}
            out["episodes"] = int(sum(e["episodes"] for e in entries))
            out["seeds"] = len(entries)
            # (successes, episodes) per seed: what the intervals are computed from
            out["runs"] = [(count(e["success"], e["episodes"]), e["episodes"]) for e in entries]
            # (episodes with that label, episodes) per seed, as "runs" for the success
            for field, labels, counts in LABEL_FIELDS:
                labelled = [e for e in entries if e.get(field)]
                if labelled:
                    out[counts] = {
                        label: [
                            (count(e[field].get(label, 0.0), e["episodes"]), e["episodes"])
                            for e in labelled
                        ]
                        for label in labels
                    }
                    out[field] = {
                        label: float(np.mean([k / n for k, n in runs]))
                        for label, runs in out[counts].items()
                    }
            for stat in CONTACT_STATS:
                values = [e.get("contacts", {}).get(stat) for e in entries]
                values = [v for v in values if v is not None]
                out[stat] = float(np.mean(values)) if values else None
            modes[mode] = out
        cells[key] = modes
    return cells, by_cell


def present_cells(cells: dict, variants, resistances, categories) -> list[tuple[str, str, str]]:
    """(variant, training resistance, category) of every cell present, in report order."""
    order = [(v, r, c) for v in variants for r in resistances for c in categories]
    return [key for key in order if key in cells]


def rate_interval(runs: list[tuple[int, int]]) -> tuple[float, float, float]:
    """(mean, low, high) of a cell's success: Wilson's interval for one run, else the two-level
    bootstrap over seeds and episodes (realikea/eval/stats.py)."""
    if len(runs) == 1:
        ((k, n),) = runs
        return (k / n, *wilson(k, n))
    return seed_interval(runs)


def measured_runs(entry: dict, measure: str) -> list[tuple[int, int]] | None:
    """(count, episodes) per seed of `measure` in one cell and mode: "success", a failure mode,
    a strategy label or "form closure" (hook or lever). None when the cell's evaluations carry
    no such labels."""
    if measure == "success":
        return entry["runs"]
    if measure in FAILURE_MODES:
        return entry.get("failure_runs", {}).get(measure)
    strategy_runs = entry.get("strategy_runs", {})
    if measure == "form closure":  # the labels are exclusive per episode: their counts add
        if not all(label in strategy_runs for label in FORM_CLOSURE):
            return None
        per_seed = zip(*(strategy_runs[label] for label in FORM_CLOSURE), strict=True)
        return [(sum(k for k, _ in seed), seed[0][1]) for seed in per_seed]
    return strategy_runs.get(measure)


def paired_differences(
    cells: dict, variants, resistances, categories, modes, measure: str = "success"
) -> list[tuple[tuple[str, str, str, str], Difference]]:
    """Every CoACD − hull (of the same preset) comparison of `measure` (success, the rate of a
    failure mode or of a strategy label) the cells allow, per training resistance, category and
    evaluation mode: ((coacd variant, resistance, category, mode), difference)."""
    pairs = [(v, "hull" + v[5:]) for v in variants if v.startswith("coacd")]
    out = []
    for coacd, hull in pairs:
        for res in resistances:
            for category in categories:
                a, b = cells.get((coacd, res, category), {}), cells.get((hull, res, category), {})
                for m in modes:
                    if m not in a or m not in b:
                        continue
                    runs_a, runs_b = measured_runs(a[m], measure), measured_runs(b[m], measure)
                    if runs_a and runs_b:
                        label = f"{measure}: {coacd} − hull, trained in {res}, {category}, in {m}"
                        out.append(((coacd, res, category, m), Difference(label, runs_a, runs_b)))
    return out


def strategy_totals(cells: dict, variants, categories) -> dict:
    """(variant, category or 'all') -> mean strategy fractions over resistances and eval modes."""
    totals = {}
    for v in variants:
        for category in [*categories, "all"]:
            fractions = [
                m["strategies"]
                for (cv, _, cc), modes in cells.items()
                if cv == v and category in (cc, "all")
                for m in modes.values()
                if "strategies" in m
            ]
            if fractions:
                totals[v, category] = {
                    s: float(np.mean([f[s] for f in fractions])) for s in STRATEGY_LABELS
                }
    return totals
