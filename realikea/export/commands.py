"""`realikea assets export|release|verify`: built configurations written as URDF, USD and MJCF
folders, the whole library as a release, and every exported model reloaded in its own tool."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from realikea.assets.catalog import Catalog
from realikea.assets.commands import OVERRIDES_HELP, refuse_resistance, selected_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.export import FORMATS
from realikea.files import repo_path
from realikea.sim.resistance import MODES, NOMINAL, mode
from realikea.sources import SOURCES

RESISTANCE_HELP = (
    f"the joint resistance the models carry (default: {NOMINAL}); recorded in each "
    "metadata.json as resistance.exported"
)


def register(commands: argparse._SubParsersAction) -> None:
    """Add export, release and verify to the `assets` sub-commands."""
    export = commands.add_parser(
        "export",
        help="write built configurations as URDF, USD or MJCF folders with metadata.json",
        description=(
            "Export built configurations (see `realikea assets build`) into "
            "OUT/<format>_<collision>/<config id>/: the model, its meshes and metadata.json. "
            "A rerun skips configurations whose export is complete and current."
        ),
    )
    which = export.add_mutually_exclusive_group()
    which.add_argument("--all", action="store_true", help="all part x base configurations")
    which.add_argument("--part", help="one part id (all bases unless --base is given)")
    export.add_argument("--base", help="one base id")
    export.add_argument("--format", required=True, choices=FORMATS)
    export.add_argument(
        "--collision", choices=SOURCES, help="collision source (default: the config's collision)"
    )
    export.add_argument("--out", type=Path, required=True, help="output folder")
    export.add_argument("--resistance", choices=MODES, default=NOMINAL, help=RESISTANCE_HELP)
    export.add_argument("overrides", nargs="*", help=OVERRIDES_HELP)
    export.set_defaults(run=run_export)

    release = commands.add_parser(
        "release",
        help="write the whole library in every format with DATASET.md and manifest.json",
        description=(
            "Export every built configuration (see `realikea assets build --all`) in each "
            "format and collision source into OUT/<format>_<collision>/<config id>/, copy "
            "DATASET.md in and write OUT/manifest.json last: every file's path, size and "
            "SHA-256 per configuration, with its fidelity certificate, and totals. A rerun "
            "skips configurations whose export is complete and current and rewrites the "
            "manifest. Hydra overrides (e.g. paths.library=DIR) go before the flags or after --."
        ),
    )
    release.add_argument("--out", type=Path, help="release folder (required unless --counts)")
    release.add_argument(
        "--collision",
        nargs="+",
        choices=SOURCES,
        default=list(SOURCES),
        help="collision sources (default: all)",
    )
    release.add_argument(
        "--formats", nargs="+", choices=FORMATS, default=list(FORMATS), help="(default: all)"
    )
    release.add_argument("--resistance", choices=MODES, default=NOMINAL, help=RESISTANCE_HELP)
    release.add_argument(
        "--counts",
        action="store_true",
        help="print the catalog counts DATASET.md quotes (YAML) and write nothing",
    )
    release.add_argument(
        "--verify",
        action="store_true",
        help="then reload every exported model in its own tool (MuJoCo, PyBullet, usd-core) "
        "and write OUT/verification.json; exit 1 if any fails",
    )
    release.add_argument("overrides", nargs="*", help=OVERRIDES_HELP)
    release.set_defaults(run=run_release)

    verify = commands.add_parser(
        "verify",
        help="reload every exported model of a release or export folder in its own tool",
        description=(
            "Reload each configuration folder of a release (those its manifest.json lists) or "
            "of an export folder (every OUT/<format>_<collision>/<config id>/) in its tool: "
            "MJCF in MuJoCo, URDF in PyBullet, USD in usd-core, checking the joint and one "
            "collision shape per convex piece against metadata.json. Writes "
            "DIR/verification.json; exits 1 if any folder fails."
        ),
    )
    verify.add_argument("folder", type=Path, help="a release folder or an export --out folder")
    verify.set_defaults(run=run_verify)


def run_export(args: argparse.Namespace) -> int:
    """Export the selected built configurations and print what was written where."""
    # imported here: the USD exporter loads usd-core's pxr, 0.4 s no other command needs
    from realikea.export.driver import export_configurations
    from realikea.fidelity.certificate import report_csv

    refuse_resistance(args.overrides, "Give the exported mode as --resistance MODE.")
    cfg = load_config(args.overrides)
    configs = selected_configurations(args, cfg, Catalog.load())
    source = args.collision or str(cfg.collision.source)
    start = time.perf_counter()
    report = export_configurations(
        configs,
        args.format,
        source,
        repo_path(cfg.paths.library),
        args.out,
        resistance=mode(args.resistance),
        fidelity_csv=report_csv(cfg),
    )
    seconds = time.perf_counter() - start
    print(
        f"{len(configs)} configurations ({args.format}, {source}, {args.resistance}) in "
        f"{seconds:.1f} s:"
        f" exported {report.exported}, up to date {report.current}"
    )
    print(f"folder: {report.folder}")
    return 0


def run_release(args: argparse.Namespace) -> int:
    """Release the whole built library (or print the catalog counts) and say what was written."""
    from realikea.export import release  # loads the exporters (usd-core's pxr)
    from realikea.fidelity.certificate import report_csv

    if args.counts:
        import yaml

        print(yaml.safe_dump({"counts": release.catalog_counts()}, sort_keys=False), end="")
        return 0
    if args.out is None:
        raise RealIkeaError("give the release folder: --out DIR (or --counts)")
    refuse_resistance(args.overrides, "Give the released mode as --resistance MODE.")
    cfg = load_config(args.overrides)
    configs = release.library_configurations()
    start = time.perf_counter()
    report = release.release_library(
        configs,
        repo_path(cfg.paths.library),
        args.out,
        args.formats,
        args.collision,
        resistance=mode(args.resistance),
        fidelity_csv=report_csv(cfg),
    )
    seconds = time.perf_counter() - start
    for name, exported in report.exported.items():
        print(f"{name}: exported {exported}, up to date {report.current[name]}")
    print(
        f"{len(configs)} configurations in {seconds:.1f} s: {report.files} files, "
        f"{report.bytes / 1e6:.1f} MB; manifest: {report.manifest}"
    )
    if report.unlisted:
        shown = ", ".join(report.unlisted[:5])
        more = f" and {len(report.unlisted) - 5} more" if len(report.unlisted) > 5 else ""
        print(f"not in the manifest ({len(report.unlisted)}): {shown}{more}")
    return verify_and_record(args.out) if args.verify else 0


def verify_and_record(folder: Path) -> int:
    """Reload every exported model under `folder` in its tool, write verification.json and print
    the counts; 1 (naming the first failures) if any failed, else 0."""
    from realikea.export import verify  # loads MuJoCo, PyBullet and usd-core's pxr

    report = verify.verify_release(folder)
    path = verify.write_verification(report)
    for name, counts in report.folders.items():
        print(f"{name}: verified {counts['ok']} of {counts['configurations']}")
    print(f"{report.checked} folders verified in {report.seconds:.1f} s; verification: {path}")
    if report.ok:
        return 0
    lines = "\n  ".join(verify.failure_lines(report))
    print(
        f"realikea: verification failed: {len(report.failures)} of {report.checked} folders do "
        f"not reload as their metadata.json describes:\n  {lines}",
        file=sys.stderr,
    )
    return 1


def run_verify(args: argparse.Namespace) -> int:
    """Verify a release or export folder (`realikea assets verify DIR`)."""
    return verify_and_record(args.folder)
