"""Copy finished stages of kept runs into a pipeline's work folder, so a launch there finds them
done: each stage's folder and its record in the source's stages.json (merged into the work
folder's, a later source's record of a stage replacing an earlier one's), never the student.

    python experiments/generalist/copy_stages.py outputs/generalist_screen/NAME_s21 \
        RESULTS/screen/distilled_pairs_knob_from_door_s21 \
        RESULTS/screen/distilled_pairs_fine_tune_s21:teacher_two_point_door_fine_tuned

A source given as RUN copies each of its stage folders (teacher_*); RUN:STAGE,STAGE only those.
`--records-from KEPT` then takes each copied stage's record from KEPT's stages.json where it has
one: a later launch that used the copied stages (and kept only its new folders) read them again,
e.g. in another resistance mode, and a launch from the copies need not read them once more.
Every source and named stage is checked before anything is copied. Exit 0, or 2 on bad input.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path

from realikea.files import atomic_write_text
from realikea.training.queue import STAGES

STAGE_PREFIX = "teacher_"


def planned(sources: list[str]) -> list[tuple[Path, list[str]]]:
    """(run folder, its stage names to copy) of each source; raises ValueError naming a bad one."""
    plan = []
    for source in sources:
        run, _, named = source.partition(":")
        folder = Path(run)
        if not folder.is_dir():
            raise ValueError(f"{run}: no such run folder")
        found = sorted(p.name for p in folder.glob(f"{STAGE_PREFIX}*") if p.is_dir())
        names = named.split(",") if named else found
        missing = [n for n in names if n not in found]
        if missing or not names:
            raise ValueError(
                f"{source}: no stage folder {', '.join(missing) or STAGE_PREFIX + '*'}"
            )
        plan.append((folder, names))
    return plan


def records(folder: Path) -> dict[str, dict]:
    path = folder / STAGES
    return {s["name"]: s for s in json.loads(path.read_text())} if path.is_file() else {}


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("work", type=Path, help="the pipeline's work folder (made if absent)")
    parser.add_argument("sources", nargs="+", help="RUN or RUN:STAGE,STAGE")
    parser.add_argument("--records-from", type=Path, help="a kept run whose records win")
    args = parser.parse_args(argv)
    try:
        plan = planned(args.sources)
        if args.records_from and not (args.records_from / STAGES).is_file():
            raise ValueError(f"--records-from {args.records_from}: no {STAGES} there")
    except ValueError as err:
        print(f"copy_stages.py: {err}", file=sys.stderr)
        return 2
    args.work.mkdir(parents=True, exist_ok=True)
    merged = records(args.work)
    for folder, names in plan:
        kept = records(folder)
        for name in names:
            shutil.rmtree(args.work / name, ignore_errors=True)
            shutil.copytree(folder / name, args.work / name)
            if name in kept:
                merged[name] = kept[name]
            print(f"{folder / name} -> {args.work / name}")
    later = records(args.records_from) if args.records_from else {}
    copied = {name for _, names in plan for name in names}
    merged |= {name: later[name] for name in copied if name in later}
    atomic_write_text(args.work / STAGES, json.dumps(list(merged.values()), indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
