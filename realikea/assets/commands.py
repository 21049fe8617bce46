"""`realikea assets ...`: build, list, gallery, import, split, export, release and verify."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from realikea.assets.build import Resistance, WorkflowSettings, build_library
from realikea.assets.catalog import Catalog, Configuration, catalog_dir
from realikea.assets.export import FORMATS, SOURCES
from realikea.assets.gallery import render_gallery
from realikea.assets.importer import import_part
from realikea.assets.split import (
    SEED,
    SPLIT_FILE,
    main_dimension,
    make_split,
    write_split,
)
from realikea.config import load_config, overrides_set
from realikea.errors import RealIkeaError
from realikea.files import repo_path

OVERRIDES_HELP = "Hydra overrides, e.g. resistance=high asset=knob workflow.coacd.threshold=0.03"


def register(parser: argparse.ArgumentParser) -> None:
    """Add the asset sub-commands to `parser`."""
    commands = parser.add_subparsers(dest="command", required=True)

    build = commands.add_parser("build", help="run the six-step workflow into MJCF folders")
    which = build.add_mutually_exclusive_group()
    which.add_argument("--all", action="store_true", help="all part x base configurations")
    which.add_argument("--part", help="one part id (all bases unless --base is given)")
    build.add_argument("--base", help="one base id")
    build.add_argument("--collision", choices=("coacd", "hull", "both"), default="both")
    build.add_argument("--out", type=Path, help="library folder (default: paths.library)")
    build.add_argument("--workers", type=int, help="processes (default: all cores)")
    build.add_argument("overrides", nargs="*", help=OVERRIDES_HELP)
    build.set_defaults(run=run_build)

    listing = commands.add_parser("list", help="print the catalog")
    listing.set_defaults(run=run_list)

    gallery = commands.add_parser("gallery", help="render a contact sheet PNG")
    gallery.add_argument("--out", type=Path, default=Path("outputs/gallery.png"))
    gallery.add_argument("--configs", type=int, default=12, help="sampled configurations")
    gallery.add_argument("overrides", nargs="*", help=OVERRIDES_HELP)
    gallery.set_defaults(run=run_gallery)

    imp = commands.add_parser("import", help="add a scanned or CAD part to the library")
    imp.add_argument("path", type=Path, help="OBJ/STL/PLY/GLB mesh in the part frame")
    imp.add_argument("--category", required=True, help="knob, two_point or finger_pull")
    imp.add_argument("--id", dest="part_id", help="part id (default: from the file name)")
    imp.add_argument("--scale", type=float, default=1.0, help="multiply coordinates (mm: 0.001)")
    imp.add_argument("--friction", default="plastic", help="surface friction class")
    imp.add_argument("overrides", nargs="*", help=OVERRIDES_HELP)
    imp.set_defaults(run=run_import)

    split = commands.add_parser(
        "split",
        help="show the train/test split of the catalog parts (realikea/catalog/split.csv); "
        "--write regenerates it",
    )
    split.add_argument("--write", action="store_true", help="write realikea/catalog/split.csv")
    split.add_argument("--seed", type=int, help="generator seed (default: the committed one)")
    split.set_defaults(run=run_split)

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


def selected_configurations(args: argparse.Namespace, cfg, catalog: Catalog) -> list[Configuration]:
    """The configurations `--all`, `--part`/`--base` or else the `asset` group select."""
    if args.all:
        return list(catalog.configurations())
    if args.part or args.base:
        return list(catalog.configurations(cfg.asset.category, args.part, args.base))
    asset = cfg.asset
    # every part of the category unless the command line names a split
    named = overrides_set(args.overrides, "asset.split")
    split = asset.split if named else "all"
    return list(
        catalog.configurations(
            asset.category, asset.part, asset.base, asset.get("kind"), split=split
        )
    )


def run_build(args: argparse.Namespace) -> int:
    cfg = load_config(args.overrides)
    configs = selected_configurations(args, cfg, Catalog.load())
    sources = ("coacd", "hull") if args.collision == "both" else (args.collision,)
    out = args.out or repo_path(cfg.paths.library)
    start = time.perf_counter()
    report = build_library(
        configs,
        WorkflowSettings.from_config(cfg),
        Resistance.from_config(cfg),
        sources,
        repo_path(cfg.paths.cache),
        out,
        workers=args.workers,
    )
    seconds = time.perf_counter() - start
    print(
        f"{len(configs)} configurations ({', '.join(sources)}) in {seconds:.1f} s:"
        f" parts built {report.parts_built}, cached {report.parts_cached};"
        f" configurations built {report.configs_built}, up to date {report.configs_cached}"
    )
    print(f"index: {report.index}")
    return 0


def run_list(args: argparse.Namespace) -> int:
    catalog = Catalog.load()
    print(
        f"{'part':<28} {'category':<12} {'family':<12} {'split':<6} {'friction':<15}"
        " dimensions (mm)"
    )
    for p in catalog.parts.values():
        dims = " ".join(f"{k}={v * 1000:g}" for k, v in p.dims.items()) or f"mesh {p.mesh_file}"
        split = catalog.split_of(p.id)
        print(f"{p.id:<28} {p.category:<12} {p.family:<12} {split:<6} {p.friction:<15} {dims}")
    print(f"\n{'base':<22} {'kind':<7} {'joint':<6} {'W x H x D (cm)':<16} {'range':<8} mount")
    for b in catalog.bases.values():
        size = f"{b.width * 100:g}x{b.height * 100:g}x{b.depth * 100:g}"
        unit = "m" if b.joint == "slide" else "rad"
        mount = f"u={b.mount_u:g} v={b.mount_v:g} roll={b.mount_roll_deg:g}deg"
        print(f"{b.id:<22} {b.kind:<7} {b.joint:<6} {size:<16} {b.travel:g} {unit:<4} {mount}")
    by_category = {c: len(catalog.parts_in(c)) for c in ("knob", "two_point", "finger_pull")}
    print(
        f"\n{len(catalog.parts)} parts {by_category} x {len(catalog.bases)} bases"
        f" = {catalog.n_configurations} configurations"
    )
    if catalog.split is not None:
        held = sum(v == "test" for v in catalog.split.values())
        print(f"split (asset.split): {len(catalog.parts) - held} train, {held} test")
    return 0


def run_gallery(args: argparse.Namespace) -> int:
    cfg = load_config(args.overrides)
    path = render_gallery(cfg, args.out, n_configs=args.configs)
    print(f"gallery: {path}")
    return 0


def run_import(args: argparse.Namespace) -> int:
    cfg = load_config(args.overrides)
    if args.scale <= 0:
        raise RealIkeaError(f"--scale must be positive, got {args.scale}")
    part = import_part(args.path, args.category, args.part_id, args.scale, args.friction, cfg)
    print(f"imported {part.id} ({part.category}) -> {part.mesh_file.parent}")
    print(f"build it: realikea assets build --part {part.id}")
    return 0


def run_split(args: argparse.Namespace) -> int:
    """Print the generated split per family; with --write, write it to the catalog's split.csv."""
    catalog = Catalog.load()
    split = make_split(catalog.parts.values(), SEED if args.seed is None else args.seed)
    families: dict[str, list] = {}
    for pid in split:
        families.setdefault(catalog.parts[pid].family, []).append(catalog.parts[pid])
    print(f"{'family':<12} {'train':>5} {'test':>4}  held out (of the family sorted by size)")
    for family, members in families.items():
        ranked = sorted(members, key=lambda p: (main_dimension(p), p.id))
        held = [
            f"{p.id} ({i + 1}/{len(ranked)})" for i, p in enumerate(ranked) if split[p.id] == "test"
        ]
        print(f"{family:<12} {len(members) - len(held):>5} {len(held):>4}  {', '.join(held)}")
    n_test = sum(v == "test" for v in split.values())
    print(f"{len(split) - n_test} train, {n_test} test ({n_test / len(split):.0%} held out)")
    path = catalog_dir() / SPLIT_FILE
    if args.write:
        write_split(path, split)
        print(f"wrote {path}")
    elif catalog.split is None:
        print(f"{path} does not exist: --write makes it")
    else:
        committed = {k: v for k, v in catalog.split.items() if k in split}
        same = committed == split
        print(f"{path} {'matches' if same else 'differs from'} this split")
    imported = [p for p in catalog.parts.values() if p.id not in split]
    if imported:
        print(f"imported parts (test unless split.csv names them): {len(imported)}")
    return 0


def run_export(args: argparse.Namespace) -> int:
    """Export the selected built configurations and print what was written where."""
    # imported here: the USD exporter loads usd-core's pxr, 0.4 s no other command needs
    from realikea.assets.export.driver import export_configurations

    cfg = load_config(args.overrides)
    configs = selected_configurations(args, cfg, Catalog.load())
    source = args.collision or str(cfg.collision.source)
    start = time.perf_counter()
    report = export_configurations(
        configs, args.format, source, repo_path(cfg.paths.library), args.out
    )
    seconds = time.perf_counter() - start
    print(
        f"{len(configs)} configurations ({args.format}, {source}) in {seconds:.1f} s:"
        f" exported {report.exported}, up to date {report.current}"
    )
    print(f"folder: {report.folder}")
    return 0


def run_release(args: argparse.Namespace) -> int:
    """Release the whole built library (or print the catalog counts) and say what was written."""
    from realikea.assets.export import release  # loads the exporters (usd-core's pxr)

    if args.counts:
        import yaml

        print(yaml.safe_dump({"counts": release.catalog_counts()}, sort_keys=False), end="")
        return 0
    if args.out is None:
        raise RealIkeaError("give the release folder: --out DIR (or --counts)")
    cfg = load_config(args.overrides)
    configs = release.library_configurations()
    start = time.perf_counter()
    report = release.release_library(
        configs, repo_path(cfg.paths.library), args.out, args.formats, args.collision
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
    from realikea.assets.export import verify  # loads MuJoCo, PyBullet and usd-core's pxr

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
