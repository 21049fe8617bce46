"""95 % intervals for the cross-evaluation (cross_eval.md): each row's success as a Wilson
interval and, per seed and evaluation preset, CoACD minus hull with Newcombe's interval
(realikea/eval/stats.py); "not significant" where that interval includes zero; then which
differences stay significant with every row's counted at once (Holm's correction).

    python experiments/fidelity_ablation/intervals.py [cross_eval.md] [--episodes 50]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from realikea.eval.stats import count, diff_interval, significant, wilson
from realikea.reports.multiplicity import Difference, holm_lines
from realikea.sources import SOURCES

HERE = Path(__file__).resolve().parent


def read_rows(path: Path) -> dict[tuple[str, str, str], float]:
    """(collision, seed, preset) -> success, from cross_eval.md's table."""
    rows = {}
    for line in path.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 9 and cells[0] in SOURCES:
            rows[(cells[0], cells[1], cells[2])] = float(cells[5])
    if not rows:
        raise SystemExit(f"{path}: no rows of the form | coacd|hull | seed | preset | ... |")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("table", nargs="?", type=Path, default=HERE / "results" / "cross_eval.md")
    parser.add_argument("--episodes", type=int, default=50, help="episodes per row")
    args = parser.parse_args()
    n = args.episodes
    rows = read_rows(args.table)
    print(f"success over {n} episodes, 95 % Wilson intervals; difference: Newcombe's interval")
    print()
    print("| seed | evaluated with | CoACD | hull | CoACD − hull | |")
    print("|---:|---|---|---|---|---|")
    family = []
    for (collision, seed, preset), rate in rows.items():
        if collision != "coacd" or ("hull", seed, preset) not in rows:
            continue
        k1, k2 = count(rate, n), count(rows[("hull", seed, preset)], n)
        (l1, u1), (l2, u2) = wilson(k1, n), wilson(k2, n)
        lo, hi = diff_interval(k1, n, k2, n)
        verdict = "significant" if significant(k1, n, k2, n) else "not significant"
        print(
            f"| {seed} | {preset} | {k1 / n:.2f} [{l1:.2f}, {u1:.2f}] | "
            f"{k2 / n:.2f} [{l2:.2f}, {u2:.2f}] | {(k1 - k2) / n:+.2f} [{lo:+.2f}, {hi:+.2f}] "
            f"| {verdict} |"
        )
        family.append(Difference(f"seed {seed}, {preset}", [(k1, n)], [(k2, n)]))
    print()
    print("\n".join(holm_lines(family, "Every row at once (Holm)")))


if __name__ == "__main__":
    main()
