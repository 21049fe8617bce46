"""The generalist's tables from the grids `evaluate.py` wrote: experiments/generalist/table.md.

    python experiments/generalist/report.py

Success per kind x category x mode with Wilson 95 % intervals for each collision source found
(coacd/, hull/), then CoACD − hull per cell and pooled over the cells with Newcombe's interval.
"""

from __future__ import annotations

from pathlib import Path

from realikea.eval.stats import describe, diff_interval, significant
from realikea.files import atomic_write_text
from realikea.reports.generalist import (
    MODES,
    difference_table,
    pooled,
    read_cells,
    success_table,
)

HERE = Path(__file__).resolve().parent


def main() -> None:
    grids = {name: read_cells(HERE / name / "cells.jsonl") for name in ("coacd", "hull")}
    grids = {name: cells for name, cells in grids.items() if cells}
    lines = ["# The generalist on the held-out parts", ""]
    for name, cells in grids.items():
        first = next(iter(cells.values()))
        lines += [
            f"## Trained with {name}, evaluated with `{first['collision']}` collision, scene "
            f"{first['scene']}, split {first['split']}, env.seed={first['seed']}, "
            f"{first['episodes']} episodes a cell, randomized poses",
            "",
            success_table(cells),
        ]
        for mode in MODES:
            k, n = pooled(cells, mode)
            if n:
                lines.append(f"- all cells, {mode}: {describe(k, n)}")
        lines.append("")
    if len(grids) == 2:
        coacd, hull = grids["coacd"], grids["hull"]
        lines += ["## CoACD vs hull", "", difference_table(coacd, hull), ""]
        for mode in MODES:
            (k1, n1), (k2, n2) = pooled(coacd, mode), pooled(hull, mode)
            if n1 and n2:
                lo, hi = diff_interval(k1, n1, k2, n2)
                verdict = "significant" if significant(k1, n1, k2, n2) else "not significant"
                lines.append(
                    f"- all cells, {mode}: {k1 / n1:.2f} vs {k2 / n2:.2f}, "
                    f"{k1 / n1 - k2 / n2:+.2f} [{lo:+.2f}, {hi:+.2f}] ({verdict})"
                )
        lines.append("")
    atomic_write_text(HERE / "table.md", "\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
