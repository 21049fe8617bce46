"""Which finger pulls the policies open, against the room each offers a fingertip: the episodes
of committed misses tables (RUN/misses/finger_pull_<kind>_<mode>[_validation].jsonl, written by
misses.py) per part, beside the part's channel and lip drop (realikea/assets/catch_geometry.py)
and the 9 mm the Franka pad needs to enter the channel.

    python experiments/generalist/finger_pull_parts.py RUN [RUN ...] --kind door [--validation]

Each RUN's tables for the chosen draw (every mode it has) are read; a RUN with none is refused
before anything is written. Two tables: each part's episodes pooled over the runs and modes (a
description: the policies, not the episodes, are the units), and each run and mode's success on
the parts whose channel is narrower than the pad against the others. Prints them and writes
FIRST_RUN/../finger_pull_<kind>_parts[_validation].md (the recipe's folder).
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

from realikea.assets.catalog import BASE_KINDS, Catalog
from realikea.assets.catch_geometry import LipCatch, catch_features_at
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.files import atomic_write_text, repo_path, shown_path
from realikea.markdown import table
from realikea.sim.resistance import MODES
from realikea.sim.robot import PAD_THICKNESS


def episode_files(run: Path, kind: str, validation: bool) -> list[tuple[str, Path]]:
    """(mode, path) of the run's per-episode misses records on the chosen draw."""
    draw = "_validation" if validation else ""
    files = [(m, run / "misses" / f"finger_pull_{kind}_{m}{draw}.jsonl") for m in MODES]
    return [(m, path) for m, path in files if path.is_file()]


def room(part: str, library: Path) -> tuple[float, float] | None:
    """The part's channel width and lip drop (m) on its built mesh; None if it has no lip."""
    mesh = next(library.glob(f"{part}__*/meshes/visual.obj"), None)
    if mesh is None:
        raise RealIkeaError(f"{part}: not built; run `realikea assets build --all` first")
    found = catch_features_at(str(mesh), "finger_pull")
    if not isinstance(found, LipCatch):
        return None
    return found.channel, found.top - found.edge_y


def mm(value: float | None) -> str:
    return f"{value * 1e3:.1f}" if value is not None else "–"


def narrow(channel: float | None) -> bool:
    """A channel the pad cannot enter (or no channel at all)."""
    return channel is None or channel < PAD_THICKNESS


def report(tables: dict[tuple[str, str], list[dict]], kind: str, draw: str, command: str) -> str:
    """The per-part table (pooled) and the per-run narrow / wide table, as markdown."""
    catalog, library = Catalog.load(), repo_path(load_config([]).paths.library)
    counts: dict[str, Counter] = {}
    for episodes in tables.values():
        for e in episodes:
            counts.setdefault(e["part"], Counter())[e["outcome"]] += 1
    rooms = {part: room(part, library) or (None, None) for part in counts}
    order = sorted(counts, key=lambda p: (rooms[p][0] or 0.0, p))
    part_rows = []
    for part in order:
        c, n = counts[part], sum(counts[part].values())
        channel, drop = rooms[part]
        part_rows.append(
            (part, catalog.split_of(part), mm(channel), mm(drop), str(n),
             f"{c['success']} ({c['success'] / n:.2f})", str(c["partial"]), str(c["fail"]))
        )  # fmt: skip
    run_rows = []
    for (run, mode), episodes in tables.items():
        cells = []
        for want in (True, False):
            chosen = [e for e in episodes if narrow(rooms[e["part"]][0]) == want]
            won = sum(e["outcome"] == "success" for e in chosen)
            cells.append(f"{won} / {len(chosen)}" if chosen else "–")
        run_rows.append((run, mode, *cells))
    pad = f"{PAD_THICKNESS * 1e3:.0f} mm"
    return "\n".join([
        f"# finger_pull {kind}: which parts open, against the room behind the lip ({draw})",
        "",
        f"`{command}`, from the episodes `python experiments/generalist/misses.py` recorded "
        "(`RUN/misses/*.jsonl`). Channel: the room behind the lip along the pull (the pad, "
        f"{pad} thick, must enter it to hook); drop: how far the lip hangs below the channel's "
        "roof (`realikea/assets/catch_geometry.py`).",
        "",
        "Every part's episodes, pooled over the runs and modes below (a description: the "
        "runs' policies, not the episodes, are the units):",
        "",
        *table(
            ("part", "split", "channel (mm)", "drop (mm)", "episodes", "success", "partial",
             "fail"),
            "llrrrrrr",
            part_rows,
        ),  # fmt: skip
        "",
        f"Each run and mode's successes on the parts whose channel is narrower than the pad "
        f"({pad}) and on the others:",
        "",
        *table(("run", "mode", f"channel < {pad}", f"channel ≥ {pad}"), "llrr", run_rows),
        "",
    ])  # fmt: skip


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, metavar="RUN", help="runs with misses/")
    parser.add_argument("--kind", choices=list(BASE_KINDS), required=True)
    parser.add_argument("--validation", action="store_true", help="the validation draw's tables")
    args = parser.parse_args(argv)
    found = {run: episode_files(run, args.kind, args.validation) for run in args.runs}
    missing = [shown_path(run) for run, files in found.items() if not files]
    if missing:
        parser.error(
            f"no finger_pull {args.kind} misses records (misses.py"
            f"{' --validation' if args.validation else ''}) in: {', '.join(missing)}"
        )
    tables = {
        (shown_path(run), mode): [json.loads(line) for line in path.open() if line.strip()]
        for run, files in found.items()
        for mode, path in files
    }
    draw = "validation draw: train parts, env.seed=2000" if args.validation else "test draw"
    command = "python experiments/generalist/finger_pull_parts.py " + " ".join(
        [*(shown_path(r) for r in args.runs), "--kind", args.kind]
        + (["--validation"] if args.validation else [])
    )
    try:
        text = report(tables, args.kind, draw, command)
    except RealIkeaError as err:
        print(f"finger_pull_parts.py: {err}", file=sys.stderr)
        return 2
    suffix = "_validation" if args.validation else ""
    out = args.runs[0].parent / f"finger_pull_{args.kind}_parts{suffix}.md"
    atomic_write_text(out, text)
    print(text)
    print(f"written: {shown_path(out)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
