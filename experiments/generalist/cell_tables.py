"""The generalist study's tables of a library grid's cells (`realikea/eval/library_grid.py`):
success per cell with Wilson intervals, and two grids' difference per cell with Newcombe's."""

from __future__ import annotations

from realikea.assets.catalog import CATEGORIES
from realikea.eval.library_grid import KINDS, cell_count
from realikea.eval.stats import diff_interval, significant, wilson
from realikea.markdown import table
from realikea.sim.resistance import MODES


def _rate(record: dict | None) -> str:
    if record is None:
        return "–"
    k, n = cell_count(record)
    lo, hi = wilson(k, n)
    return f"{k / n:.2f} [{lo:.2f}, {hi:.2f}]"


def _top_label(record: dict | None, key: str) -> str:
    """The most frequent label of `key` (strategies, failure_modes) and its share, or '–'."""
    labels = (record or {}).get(key) or {}
    if not labels or max(labels.values()) == 0.0:
        return "–"
    name = max(labels, key=labels.get)
    return f"{name} {labels[name]:.2f}"


def success_table(cells: dict) -> str:
    """Success per kind x category under each mode (Wilson 95 %), the partial openings and the
    most frequent strategy and failure mode in high ('–' for cells evaluated before the failure
    modes existed, or with no failure)."""
    rows = []
    for kind in KINDS:
        for category in CATEGORIES:
            row = [cells.get((kind, category, m)) for m in MODES]
            if not any(row):
                continue
            high = row[-1]
            rows.append([
                kind, category, *(_rate(r) for r in row),
                f"{high['partial']:.2f}" if high else "–",
                _top_label(high, "strategies"), _top_label(high, "failure_modes"),
            ])  # fmt: skip
    header = ["kind", "category", *(f"{m} S [95 %]" for m in MODES), "partial (high)",
              "strategy (high)", "failure mode (high)"]  # fmt: skip
    return "\n".join(table(header, "l" * len(header), rows)) + "\n"


def difference_markdown(cells: dict, other: dict, names=("CoACD", "hull")) -> str:
    """Both successes and their difference (Newcombe 95 %) per kind x category in each mode."""
    a, b = names
    rows = []
    for kind in KINDS:
        for category in CATEGORIES:
            values = []
            for mode in MODES:
                x, y = cells.get((kind, category, mode)), other.get((kind, category, mode))
                if x is None or y is None:
                    values.append("–")
                    continue
                (k1, n1), (k2, n2) = cell_count(x), cell_count(y)
                lo, hi = diff_interval(k1, n1, k2, n2)
                mark = "" if significant(k1, n1, k2, n2) else " (n.s.)"
                values.append(
                    f"{k1 / n1:.2f} / {k2 / n2:.2f}, {k1 / n1 - k2 / n2:+.2f} "
                    f"[{lo:+.2f}, {hi:+.2f}]{mark}"
                )
            if any(v != "–" for v in values):
                rows.append([kind, category, *values])
    header = ["kind", "category", *(f"{m}: {a} / {b}, diff" for m in MODES)]
    intro = [f"{a} − {b}, success difference per cell with Newcombe's 95 % interval:", ""]
    return "\n".join(intro + table(header, "l" * len(header), rows)) + "\n"
