"""The generalist's aims, per seed (registered in README.md, "The aims"): each group's success on
the held-out parts against its mark, the verdict and the wall time of every kept aim run:
experiments/generalist/results/aims.md, and aims.json for the docs' quotes (each cell's rate
and interval under `<recipe>/s<seed>.rates.<coacd|own>.<category>_<kind>.<mode>`).

    python experiments/generalist/aims_report.py
    python experiments/generalist/aims_report.py --superseded group_ppo  # aims_group_ppo.md, .json
    python experiments/generalist/aims_report.py --superseded student_96  # round 18's

Reads what `aims.py` kept and evaluated: results/<recipe>/s<seed>/ (cells.jsonl, wall.json,
learning_curve.png) and, for `hull_high`, results/hull_high/s<seed>_own/cells.jsonl; with
`--superseded NAME`, the aim runs of a recipe the defaults no longer train, kept in
results/<recipe>_NAME/ (their paths in aims_NAME.json: `<recipe>_NAME/s<seed>...`; a seed
without its folder there was not run on it). Point
estimates are held to the marks (the issue's aims); the Wilson 95 % interval stands beside each.
A group the registered hull finger-pull door check could not open (`hull_fp_door.py`: below
HULL_FP_DOOR_MARK on its own hull) is reported but left out of the design card's own-hull aim.
Wall time is the run's launches (wall.json); where its stages.json trained longer (stages copied
from earlier runs), that is given too, as a floor, and the time aim is left unjudged.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from aims import EVALUATIONS, GROUPS, RESULTS, SEEDS
from hull_fp_door import KEPT as HULL_FP_DOOR
from hull_fp_door import RUN as HULL_FP_DOOR_RUN
from stages import busy

from realikea.eval.library_grid import cell_count, read_cells
from realikea.eval.stats import wilson
from realikea.files import atomic_write_text
from realikea.markdown import table
from realikea.training.queue import STAGES

WALL_HOURS = 2.0  # the time aim: at most 2 h of wall time per generalist
HULL_FP_DOOR_MARK = 0.3  # the registered check: below this, the group leaves the own-hull aim
# (recipe, evaluation suffix) -> {mode: mark}: every group's point estimate at or above it
MARKS = {
    ("default", ""): {"smooth": 0.8, "high": 0.7},
    ("hull_high", "_own"): {"high": 0.7},
    ("hull_high", ""): {},  # reported (the design card's policies on CoACD), no aim
}


def hull_fp_door_opened() -> bool | None:
    """Whether the registered check opened the hull finger-pull door at the mark (None: not yet)."""
    cells = read_cells(HULL_FP_DOOR / HULL_FP_DOOR_RUN.name / "cells.jsonl")
    record = cells.get(("door", "finger_pull", "high"))
    return None if record is None else rate(record)[0] >= HULL_FP_DOOR_MARK


def excluded(recipe: str, suffix: str, opened: bool | None) -> set[tuple[str, str]]:
    """The groups left out of this evaluation's aim: the hull finger-pull door from the own-hull
    aim once the check has failed to open it."""
    if (recipe, suffix) == ("hull_high", "_own") and opened is False:
        return {("door", "finger_pull")}
    return set()


def rate(record: dict) -> tuple[float, float, float]:
    k, n = cell_count(record)
    return (k / n, *wilson(k, n))


def verdict(cells: dict, marks: dict[str, float], skip: set) -> tuple[bool | None, list[str]]:
    """Whether every counted group meets its mark in every mode (None: cells missing), and the
    groups below it as 'kind category mode value'."""
    below, missing = [], False
    for kind, category in GROUPS:
        if (kind, category) in skip:
            continue
        for mode, mark in marks.items():
            record = cells.get((kind, category, mode))
            if record is None:
                missing = True
            elif (value := rate(record)[0]) < mark:
                below.append(f"{kind} {category} {mode} {value:.2f}")
    return (None if missing else not below), below


def wall_hours(folder: Path) -> float | None:
    """The run's launches' hours (wall.json; None: not kept)."""
    wall = folder / "wall.json"
    if not wall.is_file():
        return None
    return sum(json.loads(wall.read_text())["launches_seconds"]) / 3600


def stage_hours(folder: Path) -> float | None:
    """The hours some stage of the run's stages.json was training (the union of their
    intervals): stages copied in from earlier runs count here, not in its launches."""
    path = folder / STAGES
    if not path.is_file():
        return None
    timed = [(s["began"], s["ended"]) for s in json.loads(path.read_text()) if "began" in s]
    return busy(timed) / 3600 if timed else None


def wall_text(hours: float | None, staged: float | None) -> str:
    """The wall-time line: the launches' minutes, and the stages' where they trained longer."""
    if hours is None:
        return "not kept yet"
    text = f"{hours * 60:.1f} min (`wall.json`)"
    if staged is not None and staged > hours:
        text += (
            f"; its stages trained over {staged * 60:.1f} min (`stages.json`, stages copied "
            "from earlier runs included), so the seed's time is not one run's: at least that"
        )
    return text


def seed_section(
    recipe: str, seed: int, opened: bool | None, folder: str
) -> tuple[list[str], dict]:
    """One seed's table (9 groups x each evaluation's modes) and its verdicts, from the recipe's
    run in results/<folder>/s<seed>/."""
    run = RESULTS / folder / f"s{seed}"
    hours, staged = wall_hours(run), stage_hours(run)
    copied = staged is not None and hours is not None and staged > hours
    # a seed trained partly by earlier runs (copied stages) has no one measured wall time
    within = None if hours is None or copied else hours <= WALL_HOURS
    figures: dict = {"wall_hours": hours, "stage_hours": staged, "within_time": within, "rates": {}}
    header, columns = ["kind", "category"], []
    for suffix, (modes, extra) in EVALUATIONS[recipe].items():
        cells = read_cells(run.with_name(run.name + suffix) / "cells.jsonl")
        where = "own hull" if "collision=hull" in extra else "CoACD"
        rates = figures["rates"].setdefault("own" if suffix else "coacd", {})
        for mode in modes:
            header.append(f"{mode}, {where} [95 %]")
            columns.append((cells, mode, MARKS[(recipe, suffix)].get(mode), rates))
        skip = excluded(recipe, suffix, opened)
        if MARKS[(recipe, suffix)]:
            met, below = verdict(cells, MARKS[(recipe, suffix)], skip)
            left_out = sorted(" ".join(group) for group in skip)
            figures[f"aim{suffix or '_coacd'}"] = {"met": met, "below": below, "excluded": left_out}
    rows = []
    for kind, category in GROUPS:
        row = [kind, category]
        for cells, mode, mark, rates in columns:
            record = cells.get((kind, category, mode))
            if record is None:
                row.append("–")
                continue
            value, lo, hi = rate(record)
            rates.setdefault(f"{category}_{kind}", {})[mode] = [value, lo, hi]
            flag = "" if mark is None or value >= mark else " ✗"
            row.append(f"{value:.2f} [{lo:.2f}, {hi:.2f}]{flag}")
        rows.append(row)
    time = wall_text(hours, staged)
    curve = f"{folder}/s{seed}/learning_curve.png"
    lines = [f"### `{folder}` seed {seed}", "", f"Wall time: {time}; [learning curve]({curve})", ""]
    lines += [*table(header, "l" * len(header), rows), ""]
    for key, aim in figures.items():
        if key.startswith("aim"):
            state = {None: "not all cells evaluated", True: "met", False: "missed"}[aim["met"]]
            extra = f"; below: {', '.join(aim['below'])}" if aim["below"] else ""
            extra += f"; left out: {', '.join(aim['excluded'])}" if aim["excluded"] else ""
            lines.append(f"- aim ({key.removeprefix('aim_')}): {state}{extra}")
    return [*lines, ""], figures


def recipe_folders(
    parser: argparse.ArgumentParser, superseded: str, results: Path
) -> dict[str, str]:
    """Each recipe's folder of aim runs under `results`: its own, or `<recipe>_NAME` for the
    superseded recipe NAME (a parser error if none of those exists)."""
    folders = {recipe: f"{recipe}_{superseded}" if superseded else recipe for recipe in SEEDS}
    if superseded and not any((results / f).is_dir() for f in folders.values()):
        missing = ", ".join(str(results / f) for f in folders.values())
        parser.error(f"--superseded {superseded}: no folder {missing}")
    return folders


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--superseded", metavar="NAME", default="", help="a superseded recipe: <recipe>_NAME/"
    )
    superseded = parser.parse_args(argv).superseded
    folders = recipe_folders(parser, superseded, RESULTS)
    opened = hull_fp_door_opened()
    check = {None: "not run yet", True: "opened it", False: "did not open it"}[opened]
    title = f": `{superseded}`, superseded" if superseded else ""
    lines = [
        f"# The generalist's aims, per seed{title}",
        "",
        "`python experiments/generalist/aims_report.py`: held-out (test) parts, kitchen, 50 "
        "randomized episodes a cell on draw `env.seed=1000`; success with its Wilson 95 % "
        "interval, ✗ where the point estimate is below the aim's mark (default: 0.8 in smooth, "
        f"0.7 in high, CoACD; the design card's command: 0.7 in high on its own hull). Wall "
        f"time: at most {WALL_HOURS:g} h a run. The hull finger-pull door check "
        f"(`hull_fp_door.py`, ≥ {HULL_FP_DOOR_MARK} on its own hull): {check}.",
        "",
    ]
    out = {}
    for recipe, seeds in SEEDS.items():
        for seed in seeds:
            if superseded and not (RESULTS / folders[recipe] / f"s{seed}").is_dir():
                lines += [f"### `{recipe}` seed {seed}: not run on `{superseded}`", ""]
                continue
            section, figures = seed_section(recipe, seed, opened, folders[recipe])
            lines += section
            out[f"{folders[recipe]}/s{seed}"] = figures
    name = f"aims_{superseded}" if superseded else "aims"
    atomic_write_text(RESULTS / f"{name}.md", "\n".join(lines))
    atomic_write_text(RESULTS / f"{name}.json", json.dumps(out, indent=1) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
