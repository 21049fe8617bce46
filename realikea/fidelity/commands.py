"""`realikea fidelity ...` sub-commands."""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path

from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.fidelity.meshes import load_pair
from realikea.fidelity.metric import DEFAULT_SAMPLES, FidelityResult, surface_deviation
from realikea.fidelity.report import run_report as write_report

MM = 1000.0


def register(parser: argparse.ArgumentParser) -> None:
    """Add the fidelity sub-commands to the `realikea fidelity` parser."""
    commands = parser.add_subparsers(dest="command", required=True)

    measure = commands.add_parser(
        "measure",
        help="bidirectional surface deviation of collision pieces against a visual mesh",
        description=(
            "Sample both shells uniformly by area and report the exact point-to-surface "
            "distances: E(Q->P), how far the collision shell swells out of the visual mesh, and "
            "E(P->Q), how far the visual surface lies from the collision shell."
        ),
    )
    measure.add_argument("visual", help="visual mesh file (metres)")
    measure.add_argument(
        "collision", nargs="+", help="collision mesh file(s): convex pieces, one or more per file"
    )
    measure.add_argument(
        "--samples",
        type=int,
        default=DEFAULT_SAMPLES,
        help="points per shell (default %(default)s)",
    )
    measure.add_argument("--seed", type=int, default=0, help="sampling seed (default %(default)s)")
    measure.add_argument(
        "--json", action="store_true", help="print one JSON object in metres instead of a table"
    )
    measure.set_defaults(run=run_measure)

    report = commands.add_parser(
        "report",
        help="CoACD against the convex hull over the whole library: CSV, summary, plots",
        description=(
            "Measure every part of the library with both collision sources (building missing "
            "collision meshes first, reusing the cache) and write parts.csv, summary.md, "
            "distribution.png, heatmaps_<category>.png and mesh_stats.png."
        ),
    )
    report.add_argument(
        "--out",
        type=Path,
        help="output folder (default: paths.fidelity_report)",
    )
    report.add_argument(
        "--samples",
        type=int,
        default=DEFAULT_SAMPLES,
        help="points per shell (default %(default)s)",
    )
    report.add_argument("--seed", type=int, default=0, help="sampling seed (default %(default)s)")
    report.add_argument(
        "--parts-per-category",
        type=int,
        default=2,
        help="parts per category shown in the heat maps (default %(default)s)",
    )
    report.add_argument("--workers", type=int, help="processes (default: all cores)")
    # internal: restrict the report to some parts (tests, quick looks)
    report.add_argument("--part", action="append", dest="parts", help=argparse.SUPPRESS)
    report.add_argument(
        "overrides", nargs="*", help="Hydra overrides, e.g. asset=two_point workflow.coacd.seed=1"
    )
    report.set_defaults(run=run_report)


def run_measure(args: argparse.Namespace) -> int:
    """Measure one visual mesh against its collision pieces and print the result."""
    if args.samples < 1:
        raise RealIkeaError(f"--samples must be at least 1, got {args.samples}")
    visual, pieces = load_pair(args.visual, args.collision)
    result = surface_deviation(visual, pieces, samples=args.samples, seed=args.seed)
    if args.json:
        print(json.dumps(result.to_dict()))
    else:
        print(format_table(result, args, len(visual.faces), len(pieces)))
    return 0


def format_table(
    result: FidelityResult, args: argparse.Namespace, visual_faces: int, pieces: int
) -> str:
    """A readable table of both directions in millimetres."""
    files = len(args.collision)
    lines = [
        f"visual     {args.visual} ({visual_faces:,} faces)",
        f"collision  {pieces} convex piece{'s' * (pieces != 1)} "
        f"from {files} file{'s' * (files != 1)}",
        f"samples    {len(result.q_dist):,} per shell, seed {args.seed}",
        "",
        f"{'distance (mm)':<24}{'mean':>9}{'median':>9}{'p90':>9}{'max':>9}",
    ]
    for label, dev in (
        ("E(Q->P) swelling", result.q_to_p),
        ("E(P->Q) missed surface", result.p_to_q),
    ):
        lines.append(
            f"{label:<24}{dev.mean * MM:>9.3f}{dev.median * MM:>9.3f}"
            f"{dev.p90 * MM:>9.3f}{dev.max * MM:>9.3f}"
        )
    return "\n".join(lines)


def report_command(args: argparse.Namespace) -> str:
    """The command line that reproduces a report, with every option spelled out."""
    words = ["realikea", "fidelity", "report"]
    if args.out is not None:
        words += ["--out", str(args.out)]
    words += ["--samples", str(args.samples), "--seed", str(args.seed)]
    words += ["--parts-per-category", str(args.parts_per_category)]
    for part in args.parts or ():
        words += ["--part", part]
    words += list(args.overrides)
    return shlex.join(words)


def run_report(args: argparse.Namespace) -> int:
    """Write the library-wide fidelity report and print where it went."""

    result = write_report(
        load_config(args.overrides),
        out=args.out,
        samples=args.samples,
        seed=args.seed,
        parts_per_category=args.parts_per_category,
        parts=args.parts,
        workers=args.workers,
        command=report_command(args),
    )
    print(result.headline)
    print(f"{len(result.rows)} parts in {result.seconds:.1f} s; wrote to {result.out}:")
    for path in result.files:
        print(f"  {path.name}")
    for part_id, error in result.failed.items():
        print(f"realikea: warning: part {part_id} not measured: {error}", file=sys.stderr)
    return 1 if result.failed else 0
