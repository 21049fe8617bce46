"""The generalist's tables from the grids `evaluate.py` wrote:
experiments/generalist/results/table.md.

    python experiments/generalist/report.py

Success per kind x category x mode with Wilson 95 % intervals for each grid found (coacd/ and
hull/: 1,500 iterations; coacd_2500/: the CoACD run continued to 2,500), then CoACD − hull and
2,500 − 1,500 iterations per cell and pooled over the cells with Newcombe's interval.
"""

from __future__ import annotations

from pathlib import Path

from realikea.eval.stats import describe, diff_interval, significant
from realikea.files import atomic_write_text
from realikea.reports.generalist import (
    MODES,
    difference_markdown,
    pooled,
    read_cells,
    success_table,
)

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


GRIDS = {  # folder -> what was trained
    "coacd": "CoACD, w_open2 = 2, 1,500 iterations",
    "hull": "hull, w_open2 = 2, 1,500 iterations",
    "coacd_2500": "CoACD, w_open2 = 2, continued to 2,500 iterations",
    "coacd_open2_0": "CoACD, w_open2 = 0, 1,500 iterations",
    "hull_open2_0": "hull, w_open2 = 0, 1,500 iterations",
}
COMPARISONS = (  # (grid a, grid b, title, the two columns' names)
    ("coacd", "hull", "CoACD vs hull, w_open2 = 2", ("CoACD", "hull")),
    ("coacd_open2_0", "hull_open2_0", "CoACD vs hull, w_open2 = 0", ("CoACD", "hull")),
    ("hull_open2_0", "coacd", "each source with its better bonus", ("hull 0", "CoACD 2")),
    ("coacd_2500", "coacd", "2,500 vs 1,500 iterations (CoACD)", ("2,500 its", "1,500 its")),
)


def comparison_lines(a: dict, b: dict, title: str, names: tuple[str, str]) -> list[str]:
    """Per-cell and pooled differences of two grids (a − b) with Newcombe's interval."""
    lines = [f"## {title}", "", difference_markdown(a, b, names), ""]
    for mode in MODES:
        (k1, n1), (k2, n2) = pooled(a, mode), pooled(b, mode)
        if n1 and n2:
            lo, hi = diff_interval(k1, n1, k2, n2)
            verdict = "significant" if significant(k1, n1, k2, n2) else "not significant"
            lines.append(
                f"- all cells, {mode}: {k1 / n1:.2f} vs {k2 / n2:.2f}, "
                f"{k1 / n1 - k2 / n2:+.2f} [{lo:+.2f}, {hi:+.2f}] ({verdict})"
            )
    return [*lines, ""]


def main() -> None:
    grids = {name: read_cells(RESULTS / name / "cells.jsonl") for name in GRIDS}
    grids = {name: cells for name, cells in grids.items() if cells}
    lines = ["# The generalist on the held-out parts", ""]
    for name, cells in grids.items():
        first = next(iter(cells.values()))
        lines += [
            f"## Trained with {GRIDS[name]}, evaluated with `{first['collision']}` collision, "
            f"scene {first['scene']}, split {first['split']}, env.seed={first['seed']}, "
            f"{first['episodes']} episodes a cell, randomized poses",
            "",
            success_table(cells),
        ]
        for mode in MODES:
            k, n = pooled(cells, mode)
            if n:
                lines.append(f"- all cells, {mode}: {describe(k, n)}")
        lines.append("")
    for a, b, title, names in COMPARISONS:
        if a in grids and b in grids:
            lines += comparison_lines(grids[a], grids[b], title, names)
    atomic_write_text(RESULTS / "table.md", "\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
