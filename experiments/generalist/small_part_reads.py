"""Kept runs' students on the small-part reads (round 26's `pipeline.judge_small_parts`): each
group's validation draw held to each family's smallest train part, a door on each hinge side
apart, read as the pipeline reads a teacher (`realikea.training.validation`), so a student is
set beside its teachers' reads in `stages.json`.

    python experiments/generalist/small_part_reads.py RUN... [--groups two_point_door ...]

RUN is a kept run folder (its last model_*.pt is the student). Train parts, `env.seed=2000`,
randomized poses, mean action, 50 episodes a read, the run's own collision source, resistance
and scene (its `.hydra/overrides.yaml`). Each read is kept in RUN/small_part_reads.json as it
comes, so a stopped read resumes with what is missing. Prints one table (Wilson 95 %
intervals). Exit 0, or 2 on bad input (checked for every run before any evaluation).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import yaml
from validation_rule import student

from realikea.assets.catalog import GROUPS
from realikea.eval.stats import wilson
from realikea.files import atomic_write_text
from realikea.training.validation import small_part_reads, validation_success

EPISODES = 50
READS = "small_part_reads.json"


def launch_overrides(run: Path) -> list[str]:
    """The overrides the run was launched with; raises ValueError naming a run without them."""
    path = run / ".hydra" / "overrides.yaml"
    if not path.is_file():
        raise ValueError(f"{run}: no .hydra/overrides.yaml")
    return list(yaml.safe_load(path.read_text()) or [])


def check_runs(runs: list[Path]) -> None:
    """Raises ValueError naming the first run without a student or its launch overrides."""
    for run in runs:
        student(run), launch_overrides(run)


def read_missing(run: Path, groups: list[str]) -> dict[str, dict[str, float]]:
    """Every small-part read of the run's student on `groups`, reading those not yet kept."""
    path = run / READS
    reads = json.loads(path.read_text()) if path.is_file() else {}
    checkpoint, launch = student(run), launch_overrides(run)
    for group in groups:
        for read in small_part_reads(group):
            if read in reads.get(group, {}):
                continue
            rate = validation_success(checkpoint, [group], EPISODES, launch, run.name,
                                      small_parts=read)[group]  # fmt: skip
            reads.setdefault(group, {})[read] = rate
            atomic_write_text(path, json.dumps(reads, indent=1, sort_keys=True) + "\n")
    return reads


def cell(rate: float) -> str:
    low, high = wilson(round(rate * EPISODES), EPISODES)
    return f"{rate:.2f} [{low:.2f}, {high:.2f}]"


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, metavar="RUN", help="a kept run's folder")
    parser.add_argument("--groups", nargs="+", default=["two_point_door"], choices=GROUPS,
                        metavar="GROUP", help="default: two_point_door")  # fmt: skip
    args = parser.parse_args(argv)
    try:
        check_runs(args.runs)
    except ValueError as err:
        print(f"small_part_reads.py: {err}", file=sys.stderr)
        return 2
    reads = {run: read_missing(run, args.groups) for run in args.runs}
    print(f"\n| run | group | read | success [95 %] ({EPISODES} episodes) |\n|---|---|---|---:|")
    for run, groups in reads.items():
        for group in args.groups:
            for read in small_part_reads(group):
                print(f"| {run} | {group} | {read} | {cell(groups[group][read])} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
