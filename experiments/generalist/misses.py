"""Where a committed cell's missed episodes go wrong: the cell's evaluation rerun and recorded
(`realikea eval ... record=`), each episode sorted by whether its front ever reached the success
mark, how it ended and its failure mode, whether each episode let go of a grasp (its jaws
opened after it first engaged the part), and every episode's grade by its base's hinge side, the
base and the part it ran on.

    python experiments/generalist/misses.py RUN --category finger_pull --kind door \
        --resistance smooth [--validation [--checkpoint CHECKPOINT]]

RUN is a kept aim run (results/<recipe>/s<seed>/): the cell's command comes from RUN/cells.jsonl.
The rerun must give the committed cell's fail / partial / success (the same draw and episodes),
else nothing is written. `--validation` runs the same command on the validation draw instead
(the train parts under env.seed=VALIDATION_SEED, as a checkpoint sweep does), for a diagnosis
that may choose a recipe: the test draw must not. `--checkpoint` reads another checkpoint (one
of the run's teachers) on that draw, its report named after the checkpoint's folder. A run with
no cells (a kept screen run, results/screen/<name>) is read on the validation draw only, with
the cell's command an aim run's evaluation would give its last checkpoint. Prints the tables
and writes RUN/misses/<category>_<kind>_<resistance>[_validation[_<folder>]].md, and beside it
each episode's part, base, hinge side, grade and evidence (one JSON line each, `.jsonl`; what
finger_pull_parts.py pools). An episode graded below success whose front once stood at or past
the mark was opened and then let fall back: the grade is the opening at the episode's end.
"""

from __future__ import annotations

import argparse
import json
import shlex
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
from miss_report import OPEN_ABOVE, report

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, Catalog
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.library_grid import cell_overrides, read_cells
from realikea.eval.sweep import VALIDATION_SEED, checkpoints
from realikea.files import WORKSPACE, atomic_write_text, shown_path
from realikea.sim.resistance import MODES
from realikea.tasks.outcome import OUTCOMES

STAGE_4 = "stage.3"  # the observation's one-hot of the reward stage: the engaged grasp
# what RUN/misses/*.jsonl keeps of each episode
EPISODE_KEYS = (
    "part", "base", "hinge", "outcome", "termination", "failure_mode", "peak_opening", "let_go"
)  # fmt: skip


def committed_cell(run: Path, kind: str, category: str, resistance: str) -> dict:
    """The kept run's record of one cell (its command and rates)."""
    cells = read_cells(run / "cells.jsonl")
    if (kind, category, resistance) not in cells:
        raise RealIkeaError(
            f"{shown_path(run / 'cells.jsonl')}: no {category} {kind} cell in {resistance} "
            f"(it has {sorted(cells) or 'none'})"
        )
    return cells[(kind, category, resistance)]


def screen_cell(run: Path, kind: str, category: str, resistance: str) -> dict:
    """The cell an aim run's evaluation would give a run with no cells (a screen run): its last
    checkpoint, 50 episodes on the test draw (which `--validation` replaces)."""
    _, last = checkpoints(run)[-1]
    words = cell_overrides(last, kind, category, resistance, episodes=50, seed=1000, extra=[])
    where = {"kind": kind, "category": category, "resistance": resistance}
    return where | {"command": shlex.join(["realikea", "eval", *words])}


def on_validation_draw(command: str) -> str:
    """A cell's evaluation command on the validation draw: the train parts, VALIDATION_SEED."""
    drawn = ("asset.split=", "env.seed=")
    words = [w for w in shlex.split(command) if not w.startswith(drawn)]
    return shlex.join([*words, "asset.split=train", f"env.seed={VALIDATION_SEED}"])


def with_checkpoint(command: str, checkpoint: Path) -> str:
    """A cell's evaluation command reading another checkpoint (a teacher stage's)."""
    words = [w for w in shlex.split(command) if not w.startswith("policy.path=")]
    return shlex.join([*words, f"policy.path={checkpoint}"])


def record(command: str, target: Path) -> None:
    """Rerun a cell's evaluation with its episodes recorded into `target`."""
    subprocess.run([*shlex.split(command), f"record={target}"], check=True, cwd=WORKSPACE)


def let_go(engaged: np.ndarray, aperture: np.ndarray) -> bool:
    """Whether the jaws opened (the reward's open jaws) after the episode's first engaged grasp
    (stage 4)."""
    if not engaged.any():
        return False
    return bool((aperture[int(np.argmax(engaged)) :] > OPEN_ABOVE).any())


def episodes(root: Path) -> list[dict]:
    """A recorded evaluation's episodes (every file of the v3.0 layout), each with the largest
    opening it reached and whether it let go of a grasp."""
    rows = pq.read_table(root / "meta/episodes").to_pylist()
    names = json.loads((root / "meta/info.json").read_text())["features"]["observation.state"]
    state_index = {name: k for k, name in enumerate(names["names"])}
    frames = pq.read_table(root / "data", columns=["index", "next.opening", "observation.state"])
    order = frames.column("index").to_numpy()
    opening = np.empty(frames.num_rows)
    opening[order] = np.ravel(frames.column("next.opening").to_pylist())
    state = np.empty((frames.num_rows, len(state_index)))
    state[order] = np.asarray(frames.column("observation.state").to_pylist())
    engaged, aperture = state[:, state_index[STAGE_4]] > 0.5, state[:, state_index["aperture"]]
    for row in rows:
        steps = slice(row["dataset_from_index"], row["dataset_to_index"])
        row["peak_opening"] = float(opening[steps].max())
        row["let_go"] = let_go(engaged[steps], aperture[steps])
    return rows


def check_rates(rows: list[dict], cell: dict) -> None:
    """The rerun's grades must be the committed cell's."""
    counts = Counter(r["outcome"] for r in rows)
    rerun = {o: counts[o] / len(rows) for o in OUTCOMES}
    if len(rows) != cell["episodes"] or any(abs(rerun[o] - cell[o]) > 1e-9 for o in OUTCOMES):
        raise RealIkeaError(
            f"the rerun graded {len(rows)} episodes {rerun}, the committed cell "
            f"{cell['episodes']} { ({o: cell[o] for o in OUTCOMES}) }: not the same episodes"
        )


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "run", type=Path, help="a kept aim run (results/<recipe>/s<seed>) or screen run"
    )
    parser.add_argument("--category", choices=CATEGORIES, required=True)
    parser.add_argument("--kind", choices=list(BASE_KINDS), required=True)
    parser.add_argument("--resistance", choices=list(MODES), required=True)
    parser.add_argument("--validation", action="store_true", help="on the validation draw")
    parser.add_argument(
        "--checkpoint",
        type=Path,
        help="read this checkpoint (e.g. one of the run's teachers) instead of the run's own; "
        "on the validation draw only",
    )
    args = parser.parse_args(argv)
    where = (args.run, args.kind, args.category, args.resistance)
    try:
        if args.checkpoint and not args.validation:
            raise RealIkeaError("--checkpoint reads the validation draw only: add --validation")
        if args.checkpoint and not args.checkpoint.is_file():
            raise RealIkeaError(f"--checkpoint {shown_path(args.checkpoint)}: no such file")
        if (args.run / "cells.jsonl").is_file():
            cell = committed_cell(*where)
        elif args.validation:
            cell = screen_cell(*where)
        else:
            raise RealIkeaError(
                f"{shown_path(args.run)} has no cells.jsonl: a run with no committed cells is "
                "read on the validation draw only (--validation)"
            )
    except RealIkeaError as err:
        parser.error(str(err))
    joint = BASE_KINDS[args.kind]
    mark = float(load_config().task.outcome.success[joint])
    command = on_validation_draw(cell["command"]) if args.validation else cell["command"]
    if args.checkpoint:
        command = with_checkpoint(command, args.checkpoint.resolve())
    with tempfile.TemporaryDirectory() as tmp:
        record(command, Path(tmp) / "episodes")
        rows = episodes(Path(tmp) / "episodes")
    hinges = {b.id: b.hinge for b in Catalog.load().bases.values()}
    rows = [r | {"hinge": hinges[r["base"]]} for r in rows]
    if not args.validation:
        try:
            check_rates(rows, cell)
        except RealIkeaError as err:
            print(f"misses.py: {err}; nothing written", file=sys.stderr)
            return 1
    text = report(rows, cell, mark, "m" if joint == "slide" else "rad", command)
    draw = "_validation" if args.validation else ""
    draw += f"_{args.checkpoint.parent.name}" if args.checkpoint else ""
    out = args.run / "misses" / f"{args.category}_{args.kind}_{args.resistance}{draw}.md"
    out.parent.mkdir(exist_ok=True)
    kept = [{k: r[k] for k in EPISODE_KEYS} for r in rows]
    atomic_write_text(out.with_suffix(".jsonl"), "".join(json.dumps(r) + "\n" for r in kept))
    atomic_write_text(out, text)
    print(text)
    print(f"written: {shown_path(out)}, {shown_path(out.with_suffix('.jsonl'))}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
