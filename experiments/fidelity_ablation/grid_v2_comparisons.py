"""The fidelity grid v2's four registered CoACD - hull comparisons (README.md, "The grid on
today's recipe"): each policy's value, the stratified difference with its shift interval and exact
permutation p over seeds (realikea/eval/permutation.py), Holm-corrected over the four, and their
table rows. Read by grid_v2_report.py.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from grid_v2 import CATEGORIES, COLLISIONS
from grid_v2_eval import PHASE_EPISODES, PHASE_FORCES, PHASE_FRICTION

from realikea.eval.permutation import shift_interval, stratified_difference
from realikea.eval.permutation import stratified_permutation_p as permutation_p
from realikea.eval.stats import holm, wilson

FORM_CLOSURE = ("hook", "lever")


def success(run: dict, geometry: str = "coacd", mode: str = "high") -> float:
    return run["evals"][geometry]["modes"][mode]["success"]


def share(run: dict, labels, mode: str = "high") -> float:
    """The share of the run's CoACD successes in `mode` labelled one of `labels` (0 with none)."""
    entry = run["evals"]["coacd"]["modes"][mode]
    return sum(entry["success_strategies"][label] for label in labels)


def success_counts(run: dict) -> tuple[int, int]:
    """(successes, episodes) of the run on CoACD in high."""
    entry = run["evals"]["coacd"]["modes"]["high"]
    return round(entry["success"] * entry["episodes"]), entry["episodes"]


def share_counts(run: dict, labels) -> tuple[int, int]:
    """(successes labelled one of `labels`, successes) on CoACD in high."""
    successes = success_counts(run)[0]
    return round(share(run, labels) * successes), successes


def phase_counts(run: dict) -> tuple[int, int] | None:
    """(successes, episodes) over the run's hard-pad phase-map cells, PHASE_EPISODES each."""
    value = phase_success(run)
    episodes = PHASE_EPISODES * len(PHASE_FORCES)
    return None if value is None else (round(value * episodes), episodes)


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
    counts: object  # run -> (k, n) episodes behind the value, for its episode-level interval


REGISTERED = (
    Comparison("1. two-point x high: hook share of successes", (("two_point", "high"),),
               lambda r: share(r, ("hook",)), lambda r: share_counts(r, ("hook",))),
    Comparison("2. knob x high: form-closure (hook + lever) share of successes",
               (("knob", "high"),), lambda r: share(r, FORM_CLOSURE),
               lambda r: share_counts(r, FORM_CLOSURE)),
    Comparison("3. trained in smooth, evaluated in high: success (stratified by category)",
               tuple((c, "smooth") for c in CATEGORIES), success, success_counts),
    Comparison(f"4. hard-pad phase map (mu {PHASE_FRICTION:g}, "
               f"{'/'.join(f'{f:g}' for f in PHASE_FORCES)} N): two-point x high success",
               (("two_point", "high"),), phase_success, phase_counts),
)  # fmt: skip


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


def policy_lines(runs: list[dict]) -> list[str]:
    """Each policy's value in each registered comparison, with its episodes and the Wilson
    interval over them (a share: over the policy's successes; none: no interval)."""
    lines = [
        "| comparison | policy | value | k / n episodes | episode-level [95 %] |",
        "|---|---|---:|---:|---|",
    ]
    for comparison in REGISTERED:
        number = comparison.label.split(".")[0]
        cells = set(comparison.cells)
        for run in sorted(runs, key=lambda r: r["name"]):
            if (run["category"], run["resistance"]) not in cells:
                continue
            found = comparison.counts(run)
            if found is None:
                lines.append(f"| {number} | `{run['name']}` | not yet evaluated | | |")
                continue
            (k, n), value = found, comparison.value(run)
            interval = "–" if n == 0 else "[{:.2f}, {:.2f}]".format(*wilson(k, n))
            lines.append(f"| {number} | `{run['name']}` | {value:.2f} | {k} / {n} | {interval} |")
    return lines
