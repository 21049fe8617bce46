"""Two finished runs side by side: each one's success per evaluation mode with Wilson's 95 %
interval, and A − B with Newcombe's (e.g. one seed at two schedules, which the report does not
pool)."""

from __future__ import annotations

from pathlib import Path

from realikea.eval.stats import count, diff_interval, significant, wilson
from realikea.markdown import table
from realikea.runs.records import read_eval


def _rate(k: int, n: int) -> str:
    low, high = wilson(k, n)
    return f"{k / n:.2f} [{low:.2f}, {high:.2f}]"


def comparison_lines(a: Path, b: Path) -> list[str]:
    """Markdown: per mode both successes [Wilson] and A − B [Newcombe], "not significant" where
    that interval includes zero."""
    modes_a, modes_b = read_eval(a), read_eval(b)
    rows = []
    for mode in [m for m in modes_a if m in modes_b]:
        ea, eb = modes_a[mode], modes_b[mode]
        ka, na = count(ea["success"], ea["episodes"]), ea["episodes"]
        kb, nb = count(eb["success"], eb["episodes"]), eb["episodes"]
        low, high = diff_interval(ka, na, kb, nb)
        diff = f"{ka / na - kb / nb:+.2f} [{low:+.2f}, {high:+.2f}]"
        verdict = "significant" if significant(ka, na, kb, nb) else "not significant"
        rows.append([mode, _rate(ka, na), _rate(kb, nb), diff, verdict])
    header = ["mode", "A", "B", "A − B [95 %]", "verdict"]
    return [f"A = {a}, B = {b}", "", *table(header, "lllll", rows)]
