"""A staged run's timeline (training/pipeline.py's RUN/stages.json): when each stage began and
ended, in minutes after the first began, its wall minutes, seconds per iteration,
last-window training success per group and, judged on the validation draw (`pipeline.judge:
validation`), each teacher's success there (read in other resistance modes too,
`pipeline.judge_resistances`: "0.90 / high 0.70"); the student's teacher of each group where
recorded; then the pipeline's span, the minutes of it with some
stage training (a parked run's gap between launches is not) and the stages' summed minutes
(their ratio to the former: how many trained at once on average). Last, what the launch's
time is made of: the longest chain of stages that train one after another (the pipeline's
order, `needs`), each stage's whole length at the pace it trained at, and the least wall time
those lengths allow on 2 or 4 stage slots (the teachers' summed minutes over the slots, then the
student) and on any number (the chain).

    python experiments/generalist/stages.py RESULTS/distilled_pairs_s20

A stage resumed in a later launch shows that launch's times (`resumed at`): its minutes in an
earlier launch are in no figure here but the chain's, which counts its whole length at its last
launch's pace (marked ~); the launches' wall time (wall.json) has them. Exit 0, or 2 on bad
input.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from omegaconf import OmegaConf

from realikea.assets.catalog import group_name
from realikea.training.pipeline import FINE_TUNED, RETRAIN, STUDENT, STUDENT_MORE, own_teachers
from realikea.training.queue import STAGES

SLOTS = (2, 4)  # stage slots the least wall time is given for (2: the launch's pairs)


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


def needs(record: dict, names: set[str], named: set[str]) -> list[str]:
    """The stages a finished one waited for (training/pipeline.py): a retrain its first, a
    fine-tune or a teacher starting from a kind's actor that teacher, a group teacher the
    pipeline does not name (the teacher rule's) its fine-tune if it had one, else its kind's
    teacher; the student every teacher, its more iterations the student."""
    name = record["name"]
    if name == STUDENT:
        return sorted(n for n in names if n.startswith("teacher_"))
    if name == STUDENT_MORE:
        return [STUDENT]
    if name.endswith(RETRAIN):
        return [name.removesuffix(RETRAIN)]
    if record.get("starts_from"):
        return [record["starts_from"]]
    group = group_name(record["category"], record["kind"]) if record.get("category") else ""
    if not group or group in named:
        return []
    fine_tune = f"teacher_{group}{FINE_TUNED}"
    return [fine_tune if fine_tune in names else f"teacher_{record['kind']}"]


def whole_minutes(record: dict, by_name: dict[str, dict]) -> tuple[float, bool]:
    """A stage's length had it trained in one launch, at the pace of its last, and whether that
    is estimated (it was resumed). The student's more iterations go on from its last checkpoint,
    model_<iterations - 1>, as a resume does (`resumed at`)."""
    first = by_name[STUDENT]["iterations"] - 1 if record["name"] == STUDENT_MORE else 0
    own, ran = record["iterations"] - first, record["iterations"] - record["resumed_at"]
    return record["seconds"] / 60 * own / ran, ran != own


def chain_text(stages: list[dict], named: set[str]) -> str:
    """The longest chain of stages that train one after another, and the least wall time the
    stages' whole lengths allow on `SLOTS` slots and on any number."""
    by_name = {s["name"]: s for s in stages}
    length = {name: whole_minutes(s, by_name) for name, s in by_name.items()}
    names, longest = set(by_name), {}

    def chain(name: str) -> tuple[float, list[str]]:
        if name not in longest:
            before = [chain(n) for n in needs(by_name[name], names, named) if n in by_name]
            total, path = max(before, default=(0.0, []))
            longest[name] = (total + length[name][0], [*path, name])
        return longest[name]

    total, path = max(chain(name) for name in by_name)
    steps = " → ".join(f"{n} {'~' if length[n][1] else ''}{length[n][0]:.1f}" for n in path)
    teachers = sum(m for n, (m, _) in length.items() if n.startswith("teacher_"))
    student = sum(length[n][0] for n in (STUDENT, STUDENT_MORE) if n in length)
    least = ", ".join(f"{max(total, teachers / k + student):.1f} on {k}" for k in SLOTS)
    return (f"longest chain: {steps} = {total:.1f} min. At these paces the stages need at least "
            f"{least} stage slots and {total:.1f} on any number (teachers {teachers:.1f} min "
            f"summed, student {student:.1f})")  # fmt: skip


def named_teachers(run: Path) -> set[str] | None:
    """The groups the run's pipeline names a teacher for (its .hydra/config.yaml); None without
    one."""
    config = run / ".hydra" / "config.yaml"
    return set(own_teachers(OmegaConf.load(config))) if config.is_file() else None


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
    named = named_teachers(args.run)
    if named is None:  # a group teacher waits for its kind's only if the pipeline did not name it
        print("longest chain: not known without the run's .hydra/config.yaml")
    else:
        print(chain_text(stages, named))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
