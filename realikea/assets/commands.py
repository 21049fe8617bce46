"""`realikea assets ...`: build, list, gallery, import and split (export, release and verify:
realikea/export/commands.py, registered in the same group by realikea/cli.py)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from realikea.assets.build import WorkflowSettings, build_library
from realikea.assets.catalog import Catalog, Configuration, catalog_dir
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
from realikea.sim.resistance import NOMINAL
from realikea.sources import SOURCES

OVERRIDES_HELP = "Hydra overrides, e.g. asset=knob workflow.coacd.threshold=0.03 paths.library=DIR"


def register(parser: argparse.ArgumentParser) -> argparse._SubParsersAction:
    """Add the asset sub-commands to `parser`; returns them, for the export commands."""
    commands = parser.add_subparsers(dest="command", required=True)

    build = commands.add_parser("build", help="run the six-step workflow into MJCF folders")
    which = build.add_mutually_exclusive_group()
    which.add_argument("--all", action="store_true", help="all part x base configurations")
    which.add_argument("--part", help="one part id (all bases unless --base is given)")
    build.add_argument("--base", help="one base id")
    build.add_argument("--collision", choices=(*SOURCES, "both"), default="both")
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
    return commands


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


def refuse_resistance(overrides: list[str], instead: str) -> None:
    """Refuse a `resistance` override where the library is read or written, naming `instead`:
    the built library carries the nominal mode and a mode is applied by the scene or export."""
    if overrides_set(overrides, "resistance"):
        raise RealIkeaError(
            f"the built library is written at the nominal resistance ({NOMINAL}) whatever a run "
            f"uses; a resistance override does nothing here. {instead}"
        )


def run_build(args: argparse.Namespace) -> int:
    refuse_resistance(
        args.overrides,
        "Training and evaluation apply `resistance=` where they build the scene; an export "
        "takes `--resistance`.",
    )
    cfg = load_config(args.overrides)
    configs = selected_configurations(args, cfg, Catalog.load())
    sources = SOURCES if args.collision == "both" else (args.collision,)
    out = args.out or repo_path(cfg.paths.library)
    start = time.perf_counter()
    report = build_library(
        configs,
        WorkflowSettings.from_config(cfg),
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
