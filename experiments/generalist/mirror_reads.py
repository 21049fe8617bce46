"""Kept runs' students on the doors' small-part reads with the mirror off (as trained) and on
(`task.mirror_doors`: each door whose arm starts mirrored seen and driven as its hinge twin,
`realikea/tasks/mirror.py`), so a student that opens one hinge side and not the other shows
whether its skill on the one carries to the other reflected.

    python experiments/generalist/mirror_reads.py RUN... [--groups two_point_door ...]

RUN is a kept run folder (its last model_*.pt is the student). The small-part reads of
`small_part_reads.py` (train parts, `env.seed=2000`, randomized poses, mean action, 50 episodes
a read, the run's own collision source, resistance and scene): describing, part of no rule.
Each read is kept in RUN/mirror_reads.json as it comes, so a stopped read resumes with what is
missing. Prints one table (Wilson 95 % intervals; differences with Newcombe's). Exit 0,
or 2 on bad input (checked for every run before any evaluation).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from small_part_reads import EPISODES, cell, check_runs, launch_overrides
from validation_rule import student

from realikea.assets.catalog import GROUPS, kind_and_category
from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.stats import count, diff_interval
from realikea.files import atomic_write_text
from realikea.tasks.open_task import OpenTask
from realikea.training.validation import (
    SMALL_PART_SIDES,
    small_part_overrides,
    small_part_reads,
    validation_overrides,
)

READS = "mirror_reads.json"
DOOR_GROUPS = [g for g in GROUPS if kind_and_category(g)[0] == "door"]


def mirrored_read(group: str) -> str:
    """The group's small-part read on the hinge side the mirror reflects (left-hinged doors,
    or right-hinged where the placement turns the hand: `OpenTask.mirrored`)."""
    _, category = kind_and_category(group)
    for small in small_part_reads(group):
        overrides = small_part_overrides(group, small)
        cfg = load_config([f"asset={category}", "asset.kind=door", "task.mirror_doors=true",
                           *overrides])  # fmt: skip
        (mjcf,) = training_configurations(cfg, 1)
        if OpenTask(cfg, mjcf).mirrored:
            return small
    raise ValueError(f"{group}: no door of either hinge side is mirrored")


def read(checkpoint: Path, group: str, small: str, launch: list[str], mirrored: bool) -> float:
    """The student's success on one small-part read with the mirror set as named (not the
    checkpoint's own task setting)."""
    cfg, policy = eval_setup(validation_overrides(checkpoint, group, EPISODES, launch, "", small))
    cfg.task.mirror_doors = mirrored
    return float(evaluate(cfg, policy, progress=False).summary()["success"])


def read_missing(run: Path, groups: dict[str, str]) -> dict:
    """Every read of the run's student on `groups` (each with its mirrored read): both hinge
    sides with the mirror off, the mirrored side with it on; reads those not yet kept."""
    path = run / READS
    reads = json.loads(path.read_text()) if path.is_file() else {}
    checkpoint, launch = student(run), launch_overrides(run)
    for group, mirrored in groups.items():
        for small, setting in [(s, "off") for s in small_part_reads(group)] + [(mirrored, "on")]:
            kept = reads.setdefault(group, {}).setdefault(small, {})
            if setting not in kept:
                kept[setting] = read(checkpoint, group, small, launch, setting == "on")
                print(f"{run.name} {group} {small} mirror {setting}: {kept[setting]:.2f}",
                      flush=True)  # fmt: skip
                atomic_write_text(path, json.dumps(reads, indent=1, sort_keys=True) + "\n")
    return reads


def difference(k1: int, k2: int) -> str:
    low, high = diff_interval(k1, EPISODES, k2, EPISODES)
    return f"{(k1 - k2) / EPISODES:+.2f} [{low:+.2f}, {high:+.2f}]"


def row(run: Path, group: str, mirrored: str, reads: dict[str, dict[str, float]]) -> str:
    """One table row: the mirrored side off and on, its twin side off, and the differences."""
    (twin,) = [s for s in small_part_reads(group) if s != mirrored]
    rates = [reads[mirrored]["off"], reads[mirrored]["on"], reads[twin]["off"]]
    off, on, twin_off = (count(rate, EPISODES) for rate in rates)
    side = SMALL_PART_SIDES[mirrored]
    return (f"| {run} | {group} | {side} | {' | '.join(map(cell, rates))} | "
            f"{difference(on, off)} | {difference(on, twin_off)} |")  # fmt: skip


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, metavar="RUN", help="a kept run's folder")
    parser.add_argument("--groups", nargs="+", default=["two_point_door"], choices=DOOR_GROUPS,
                        metavar="GROUP", help="door groups (default: two_point_door)")  # fmt: skip
    args = parser.parse_args(argv)
    try:
        check_runs(args.runs)
        groups = {group: mirrored_read(group) for group in args.groups}
    except ValueError as err:
        print(f"mirror_reads.py: {err}", file=sys.stderr)
        return 2
    reads = {run: read_missing(run, groups) for run in args.runs}
    print(f"\n{EPISODES} episodes a read, Wilson 95 % intervals; differences with Newcombe's.\n")
    print(
        "| run | group | mirrored side | mirror off | mirror on | twin side (off) "
        "| on - off | on - twin |\n|---|---|---|---:|---:|---:|---:|---:|"
    )
    for run, kept in reads.items():
        for group, mirrored in groups.items():
            print(row(run, group, mirrored, kept[group]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
