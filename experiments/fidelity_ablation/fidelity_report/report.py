"""The report: finished runs and phase maps assembled into report.md beside its figures."""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

from realikea.errors import RealIkeaError
from realikea.files import atomic_write_text
from realikea.reports.multiplicity import holm_lines
from realikea.runs.records import find_runs, unfinished_runs
from realikea.sim.resistance import MODES
from realikea.sources import SOURCES

from .cells import (
    aggregate,
    ordered,
    paired_differences,
    strategy_totals,
)
from .phase_maps import phase_map_lines
from .plots import (
    plot_learning_curves,
    plot_outcomes,
    plot_strategies,
    plot_success,
)
from .tables import (
    compute_lines,
    difference_lines,
    failure_lines,
    interval_lines,
    outcome_tables,
    per_run_lines,
    relative,
    strategy_lines,
)
from .videos import frame_lines

# the report's CoACD − hull tables, (evaluation modes, None = every mode; measure): the family
# Holm's correction counts; success comes first, in its own table before the failure modes
TESTED = ((None, "success"), (["high"], "slip"), (["high"], "hook"), (["high"], "form closure"))


def report(roots: list[Path], out: Path, phase_maps: Sequence[Path] = ()) -> Path:
    """Write out/report.md and its figures from the finished runs under `roots` and the phase
    maps; returns the report's path."""
    runs = find_runs(roots)
    unfinished = unfinished_runs(roots)
    for run in unfinished:
        print(f"not in the report (no eval.json yet): {run}", file=sys.stderr)
    if not runs:
        raise RealIkeaError(f"no finished runs (eval.json + .hydra/config.yaml) under {roots}")
    maps = phase_map_lines(phase_maps, out)  # checked before anything is written
    cells, by_cell = aggregate(runs)
    variants = ordered({k[0] for k in cells}, SOURCES)
    resistances = ordered({k[1] for k in cells}, MODES)
    categories = ordered({k[2] for k in cells}, ("knob", "finger_pull", "two_point"))
    modes = ordered({m for c in cells.values() for m in c}, MODES)
    totals = strategy_totals(cells, variants, categories)
    axes = (cells, variants, resistances, categories)
    out.mkdir(parents=True, exist_ok=True)
    plot_success(cells, variants, resistances, categories, modes, out / "success.png")
    plot_outcomes(cells, variants, resistances, categories, modes, out / "outcomes.png")
    plot_strategies(totals, variants, categories, out / "strategies.png")
    plot_learning_curves(by_cell, variants, resistances, categories, out / "learning_curves.png")
    root = roots[0] if len(roots) == 1 else Path.cwd()
    lines = [
        "# Fidelity ablation",
        "",
        provenance(runs, roots),
        "",
        "![success](success.png)",
        "",
        *interval_lines(cells, by_cell, variants, resistances, categories, modes),
        "",
        *tested_lines(axes, modes),
        "",
        *outcome_tables(cells, variants, resistances, categories, modes),
        "",
        "![outcomes](outcomes.png)",
        "",
        *strategy_lines(cells, totals, variants, categories),
        "",
        "![strategies](strategies.png)",
        "",
        "## Learning curves",
        "",
        "![learning curves](learning_curves.png)",
        "",
        *per_run_lines(runs, root),
        "",
        *compute_lines(runs, root),
    ]
    if unfinished:
        lines += [
            "",
            "Not counted (no eval.json yet): " + ", ".join(relative(r, root) for r in unfinished),
        ]
    lines += ["", *maps, "", *frame_lines(runs, out)]
    path = out / "report.md"
    atomic_write_text(path, "\n".join(lines) + "\n")
    return path


def provenance(runs: list[dict], roots: list[Path]) -> str:
    """The report's first sentence: which runs, scene, split, presets, seeds and episodes."""
    presets = sorted({(r["gripper"], r["contact"]) for r in runs})
    episodes = sorted({r["eval"]["episodes"] for r in runs})
    splits = sorted({r["eval"].get("split", "all") for r in runs})
    scenes = sorted({r["scene"] for r in runs})
    seeds = sorted({r["seed"] for r in runs})
    return (
        f"{len(runs)} runs from {', '.join(str(r) for r in roots)}; scene "
        f"{', '.join(scenes)}; evaluation split {'/'.join(splits)}; "
        f"gripper/contact presets: {', '.join('/'.join(p) for p in presets)}; "
        f"training seeds {', '.join(map(str, seeds))}; "
        f"{'/'.join(map(str, episodes))} evaluation episodes per run and mode "
        "(`train.eval_after`, the last checkpoint)."
    )


def tested_lines(axes: tuple, modes: list[str]) -> list[str]:
    """The CoACD − hull tables of TESTED (success first, then the failure modes' table, then
    the others) and Holm's correction over all of their differences at once."""
    cells, variants, resistances, categories = axes
    return [
        *difference_lines(*axes, modes),
        "",
        *failure_lines(cells, variants, resistances, categories),
        "",
        *[
            line
            for tested_modes, measure in TESTED[1:]
            for line in [*difference_lines(*axes, tested_modes, measure), ""]
        ],
        *holm_lines(
            [
                diff
                for tested_modes, measure in TESTED
                for _, diff in paired_differences(*axes, tested_modes or modes, measure)
            ],
            "Every difference at once (Holm)",
        ),
    ]
