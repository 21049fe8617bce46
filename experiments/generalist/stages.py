"""A staged run's timeline (training/pipeline.py's RUN/stages.json): when each stage began and
ended, in minutes after the first began, its wall minutes, seconds per iteration,
last-window training success per group and, judged on the validation draw (`pipeline.judge:
validation`), each teacher's success there (read in other resistance modes too,
`pipeline.judge_resistances`: "0.90 / high 0.70"); the student's teacher of each group where
recorded; then the pipeline's span, the minutes of it with some
stage training (a parked run's gap between launches is not) and the stages' summed minutes
(their ratio to the former: how many trained at once on average).

    python experiments/generalist/stages.py RESULTS/distilled_pairs_s20

A stage resumed in a later launch shows that launch's times (`resumed at`): its minutes in an
earlier launch are in no figure here, the launches' wall time (wall.json) has them. Exit 0, or 2
on bad input.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from realikea.training.queue import STAGES


def minutes(seconds: float | None) -> str:
    return "–" if seconds is None else f"{seconds / 60:.1f}"


def busy(intervals: list[tuple[float, float]]) -> float:
    """The length of the union of (start, end) intervals."""
    total, reach = 0.0, float("-inf")
    for start, end in sorted(intervals):
        total += max(0.0, end - max(start, reach))
        reach = max(reach, end)
    return total


def validation(record: dict, group: str) -> str:
    """A teacher's validation reads of a group: the launch's mode, then each other mode read."""
    others = [(k.removeprefix("validation_"), v[group]) for k, v in record.items()
              if k.startswith("validation_") and group in v]  # fmt: skip
    return " / ".join([f"{group} {record['validation'][group]:.2f}",
                       *(f"{mode} {v:.2f}" for mode, v in others)])  # fmt: skip


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", type=Path, metavar="RUN_DIR", help="a staged run's folder")
    args = parser.parse_args(argv)
    path = args.run / STAGES
    if not path.is_file():
        print(f"stages.py: no {STAGES} in {args.run}", file=sys.stderr)
        return 2
    stages = json.loads(path.read_text())
    timed = [s for s in stages if "began" in s]
    start = min((s["began"] for s in timed), default=None)
    print("| stage | began | ended | min | iterations | s/it | resumed at | success | validation |")
    print("|---|---:|---:|---:|---:|---:|---:|---|---|")
    for s in stages:
        began = s["began"] - start if "began" in s else None
        ended = s["ended"] - start if "ended" in s else None
        per_iteration = s["seconds"] / (s["iterations"] - s["resumed_at"])
        success = ", ".join(f"{g} {v:.2f}" for g, v in s["success"].items())
        judged = ", ".join(validation(s, g) for g in s.get("validation", {})) or "–"
        times = f"{minutes(began)} | {minutes(ended)} | {minutes(s['seconds'])}"
        print(f"| {s['name']} | {times} | {s['iterations']} | {per_iteration:.2f} | "
              f"{s['resumed_at']} | {success} | {judged} |")  # fmt: skip
    for s in stages:
        if "teachers" in s:  # the student's (pipelines before best_teacher did not record them)
            taught = ", ".join(f"{g} from {t}" for g, t in s["teachers"].items())
            print(f"{s['name']}'s teachers: {taught}")
    summed = sum(s["seconds"] for s in stages)
    if timed:
        span = max(s["ended"] for s in timed) - start
        training = busy([(s["began"], s["ended"]) for s in timed])
        print(f"span {minutes(span)} min (first began to last ended, {len(timed)} timed stages), "
              f"{minutes(training)} min of it with a stage training; "
              f"stages' minutes summed {minutes(summed)}; "
              f"{sum(s['seconds'] for s in timed) / training:.2f} at once on average")  # fmt: skip
    else:
        print(f"stages' minutes summed {minutes(summed)} (no stage timed)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
