"""The friction-trap phase map: grip force x pad friction x friction cone for scripted
baselines and trained checkpoints on held-out drawers in high resistance.

    python experiments/fidelity_ablation/phase_map.py                      # the baselines
    python experiments/fidelity_ablation/phase_map.py --policies \
        coacd=experiments/fidelity_ablation/results/grid/coacd_high_two_point_s0/model_899.pt \
        hull=experiments/fidelity_ablation/results/grid/hull_high_two_point_s0/model_899.pt \
        --categories two_point

Appends one JSON line per cell to RESULTS (cells already there are skipped: an interrupted map
continues), then writes phase_map.md (tables) and phase_map.png (heat maps with the boundary
2 mu F = the required pull) beside it from every cell in RESULTS. `--report-only` skips the
evaluation.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from realikea.errors import RealIkeaError
from realikea.files import atomic_write_text
from realikea.reports.multiplicity import holm_lines
from realikea.reports.phase_map import (
    CONES,
    FORCES,
    FRICTIONS,
    check_axes,
    difference_grid_lines,
    differences,
    evaluate_phase_map,
    map_policy,
    phase_table,
    plot_phase_map,
    read_cells,
    required_pull,
)

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results" / "phase_map" / "cells.jsonl"
# where each default axis value comes from (datasheets and handbook tables)
AXIS_SOURCES = HERE / "phase_map_axes.md"


def write_report(results: Path, compare: tuple[str, str] = ("coacd", "hull")) -> Path:
    """phase_map.md and phase_map.png beside `results`, from every cell in it; with the
    success difference of the two `compare` policies where both were mapped."""
    cells = read_cells(results)
    if not cells:
        raise RealIkeaError(f"{results}: no cells to report")
    pull = required_pull()
    png = plot_phase_map(cells, pull, results.with_name("phase_map.png"))
    lines = [
        "# Friction-trap phase map",
        "",
        f"Drawers, high resistance (breakaway {pull:g} N at the handle), test parts, kitchen,",
        "randomized poses; the Franka Hand with its grip per jaw and pad friction set per cell.",
        "Command per cell in `cells.jsonl`.",
        "",
        f"![phase map]({png.name})",
        "",
        AXIS_SOURCES.read_text(),
        *phase_table(cells, pull),
        *difference_grid_lines(cells, *compare),
    ]
    family = list(differences(cells, *compare).values())
    if family:
        lines += ["", *holm_lines(family, "Every compared cell at once (Holm)")]
    out = results.with_name("phase_map.md")
    atomic_write_text(out, "\n".join(lines))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--policies", nargs="+", default=["heuristic_pull", "grasp_sampler"])
    parser.add_argument("--categories", nargs="+", default=["knob", "finger_pull", "two_point"])
    parser.add_argument("--forces", nargs="+", type=float, default=list(FORCES))
    parser.add_argument("--frictions", nargs="+", type=float, default=list(FRICTIONS))
    parser.add_argument("--cones", nargs="+", default=list(CONES))
    parser.add_argument("--episodes", type=int, default=20, help="episodes per cell")
    parser.add_argument("--seed", type=int, default=1000, help="env.seed of the draw")
    parser.add_argument("--results", type=Path, default=RESULTS)
    parser.add_argument("--report-only", action="store_true")
    parser.add_argument(
        "--compare", nargs=2, default=["coacd", "hull"], metavar=("A", "B"),
        help="policy labels whose success difference A − B the report tabulates",
    )  # fmt: skip
    args = parser.parse_args()
    try:
        check_axes(args.forces, args.frictions, args.cones, args.categories)
        if not args.report_only:
            policies = [map_policy(p) for p in args.policies]
            evaluate_phase_map(
                policies, args.categories, args.results, args.forces, args.frictions,
                args.cones, args.episodes, args.seed,
            )  # fmt: skip
        print(f"report: {write_report(args.results, tuple(args.compare))}")
    except RealIkeaError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
