"""The generalist screen's runs (registered in README.md, "One policy on every seed: the
candidates' screen" and its later rounds): each candidate on seeds 20 and 21, one run at a time,
alone on the machine.

    python experiments/generalist/screen.py                         # the last round's candidates
    python experiments/generalist/screen.py --round 1 --candidates distilled --seeds 20
    python experiments/generalist/screen.py --dry-run               # states and commands
    python experiments/generalist/screen.py --park                  # stopped runs into git
    python experiments/generalist/screen_rule.py RESULTS/group_ppo_s20 RESULTS/group_ppo_s21

RESULTS is experiments/generalist/results/screen. Runs train in outputs/generalist_screen/NAME
(resumable: the run queue, realikea/training/queue.py) and are kept in RESULTS/NAME (slim last
checkpoint, metrics, config, wall time); the candidates are in screen_candidates.py. A
candidate's runs on one seed (its pipeline) share BUDGET_SECONDS of wall time, every stage
counted: a run still training when its pipeline's launches reach it is stopped there and kept as
it is. A distilled candidate trains one teacher per kind, gives a group its own teacher where the
candidate names one (on its seed) or its kind's teacher missed it (on the next seed, once), then
distils every group's teacher into one student; the candidate is judged on its last run (the
student). A staged candidate (`STAGED`) is one launch of the training pipeline that does all of
this itself (realikea/training/pipeline.py), kept with its stages and judged on its student, the
launch's own checkpoint. A candidate whose kept (last) run misses its round's mark
(screen_rule.MARKS) is not run on the seeds after it.
"""

from __future__ import annotations

import argparse
import json
import sys
from contextlib import nullcontext
from pathlib import Path

from screen_candidates import (
    CANDIDATES,
    COMMON,
    DISTILLED,
    ONE_RUN,
    ROUND_1,
    ROUNDS,
    SINGLE_RUN,
    STAGED,
    STUDENT_ITERATIONS,
    TEACHER_ITERATIONS,
    TEACHER_SWITCH,
)
from screen_rule import LEARNED, MARKS, PAD_ENTERS_ROUNDS, last_window, passes

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, group_name
from realikea.config import load_config
from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE
from realikea.training.pipeline import final_iterations
from realikea.training.queue import QueuedRun, RunQueue, keep_run

HERE = Path(__file__).resolve().parent
KEPT = HERE / "results/screen"
PARKED = HERE / "results/screen_parked"
WORK = WORKSPACE / "outputs/generalist_screen"
SEEDS = (20, 21)
BUDGET_SECONDS = 2 * 3600


def run_name(candidate: str, seed: int, stage: str = "") -> str:
    return f"{candidate}_s{seed}" + (f"/{stage}" if stage else "")


def single_run(candidate: str, seed: int) -> QueuedRun:
    overrides, iterations = SINGLE_RUN[candidate]
    return QueuedRun(
        run_name(candidate, seed),
        (*COMMON, *ONE_RUN, *overrides, f"env.seed={seed}", f"agent.max_iterations={iterations}"),
        iterations,
    )


def staged_run(candidate: str, seed: int) -> QueuedRun:
    """One launch training every stage of the candidate's pipeline; its student is its last,
    as long as the composed pipeline says."""
    overrides = (*COMMON, *STAGED[candidate], f"env.seed={seed}")
    iterations = final_iterations(load_config(overrides))
    return QueuedRun(run_name(candidate, seed), overrides, iterations, staged=True)


def teacher_run(candidate: str, seed: int, kind: str, category: str = "") -> QueuedRun:
    """The teacher of one kind's groups, or (`category`) a group's own teacher: as the
    candidate names it (`DISTILLED`), else by the teacher rule, trained on the next seed."""
    extra, own = DISTILLED[candidate]
    group = group_name(category, kind) if category else ""
    iterations, switch = own.get(group, (TEACHER_ITERATIONS, TEACHER_SWITCH))
    # the teacher rule's own teacher trains on the next seed (its kind's missed on this one)
    trained_on = seed + 1 if category and group not in own else seed
    scope = (f"asset={category}",) if category else ()
    return QueuedRun(
        run_name(candidate, seed, f"teacher_{group or kind}"),
        (*COMMON, *ONE_RUN, *ROUND_1, *extra, *scope, f"asset.kind={kind}",
         f"env.seed={trained_on}", f"agent.max_iterations={iterations}",
         f"dr.switch_iteration={switch}"),
        iterations,
    )  # fmt: skip


def student_run(candidate: str, seed: int, teachers: dict[str, Path]) -> QueuedRun:
    listed = ", ".join(f"{group}: {path}" for group, path in teachers.items())
    return QueuedRun(
        run_name(candidate, seed, "student"),
        (*COMMON, *ONE_RUN, *ROUND_1, *DISTILLED[candidate][0], f"distill.teachers={{{listed}}}",
         f"env.seed={seed}", f"agent.max_iterations={STUDENT_ITERATIONS}",
         "dr.switch_iteration=0"),
        STUDENT_ITERATIONS,
    )  # fmt: skip


def last_checkpoint(run: QueuedRun) -> str:
    return f"model_{run.iterations - 1}.pt"


def pipeline(run: QueuedRun) -> str:
    """The candidate-and-seed folder a run belongs to (a stage's parent)."""
    return run.name.split("/")[0]


class Screen:
    """The screen's run queue, with each pipeline's wall-time budget."""

    def __init__(self, work: Path = WORK, kept: Path = KEPT, parked: Path | None = PARKED):
        self.kept_dir = kept
        self.queue = RunQueue(
            work,
            last_checkpoint,
            lambda run, seconds: keep_run(
                work / run.name, kept / run.name, seconds, staged=run.staged
            ),
            lambda run: (kept / run.name / "wall.json").is_file(),
            self.over_budget,
            parked,
        )

    def spent(self, name: str) -> float:
        """Wall seconds the launches of the pipeline `name` (a single run, or a folder of
        stages) have taken so far, kept or training."""
        stages = {
            p.name.removesuffix(".wall.json") for p in (self.queue.work / name).glob("*.wall.json")
        }
        stages |= {p.parent.name for p in (self.kept_dir / name).glob("*/wall.json")}
        return sum(self.seconds(r) for r in [name, *(f"{name}/{s}" for s in stages)])

    def seconds(self, name: str) -> float:
        """The wall seconds of one run's launches: as kept, else as the queue records them."""
        kept = self.kept_dir / name / "wall.json"
        if kept.is_file():
            return sum(json.loads(kept.read_text())["launches_seconds"])
        return sum(self.queue.wall_times(QueuedRun(name, (), 0)))

    def over_budget(self, run: QueuedRun) -> bool:
        return self.spent(pipeline(run)) >= BUDGET_SECONDS

    def stage(self, runs: list[QueuedRun], dry_run: bool, park: bool) -> bool:
        """Train `runs` (or show or park them); whether all of them are kept."""
        name = pipeline(runs[0]) if runs else ""
        if runs and not (dry_run or park) and self.spent(name) >= BUDGET_SECONDS:
            print(f"{name}: its {BUDGET_SECONDS / 3600:.0f} h are spent; it fails this seed")
            return False
        self.run(runs, dry_run, park)
        return all(self.queue.kept(r) for r in runs)

    def run(self, runs: list[QueuedRun], dry_run: bool, park: bool) -> int:
        return self.queue.serve(runs, 1, dry_run=dry_run, park=park)

    def single(self, candidate: str, seed: int, mark: float, dry_run: bool, park: bool,
               reading: bool = False) -> bool:  # fmt: skip
        """Train (or show or park) a candidate's one run on one seed (a single run, or a staged
        candidate's launch); whether its seeds after this one still run (not once its kept run
        misses `mark` in some group, read as `screen_rule.last_window(..., reading)`)."""
        run = (staged_run if candidate in STAGED else single_run)(candidate, seed)
        self.stage([run], dry_run, park)
        kept = self.queue.kept(run)
        if kept and not passes(last_window(self.kept_dir / run.name, reading), mark):
            print(f"{run.name} misses {mark:g} in some group: {candidate} stops at this seed")
            return False
        return True

    def distilled(self, candidate: str, seed: int, mark: float, reading: bool, dry_run: bool,
                  park: bool) -> bool:  # fmt: skip
        """Teachers per kind, each group's own teacher where the candidate names one or its
        kind's teacher missed it, then the student (each stage once the one before is kept);
        whether its seeds after this one still run (not once the student misses `mark` in some
        group, read as `screen_rule.last_window(..., reading)`)."""
        kinds = {kind: teacher_run(candidate, seed, kind) for kind in BASE_KINDS}
        for run in kinds.values():
            if not self.stage([run], dry_run, park) and not (dry_run or park):
                return True
        if not all(self.queue.kept(r) for r in kinds.values()):
            return True  # shown or parked
        own, teachers = DISTILLED[candidate][1], {}
        for kind, run in kinds.items():
            values = last_window(self.kept_dir / run.name)
            for category in CATEGORIES:
                group = group_name(category, kind)
                if group in own or (values[group] or 0.0) < LEARNED:
                    teachers[group] = teacher_run(candidate, seed, kind, category)
                    if not self.stage([teachers[group]], dry_run, park):
                        return True
                else:
                    teachers[group] = run
        paths = {g: checkpoints(self.kept_dir / r.name)[-1][1] for g, r in teachers.items()}
        student = student_run(candidate, seed, paths)
        self.stage([student], dry_run, park)
        if self.queue.kept(student) and not passes(
            last_window(self.kept_dir / student.name, reading), mark
        ):
            print(f"{student.name} misses {mark:g} in some group: {candidate} stops at this seed")
            return False
        return True


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--round", type=int, choices=list(ROUNDS), default=max(ROUNDS))
    parser.add_argument("--candidates", nargs="+", choices=CANDIDATES, help="default: the round's")
    parser.add_argument("--seeds", nargs="+", type=int, default=list(SEEDS))
    parser.add_argument("--dry-run", action="store_true", help="print the runs and stop")
    parser.add_argument("--park", action="store_true", help="stop at next checkpoints; copy to git")
    args = parser.parse_args(argv)
    foreign = sorted(set(args.candidates or ()) - set(ROUNDS[args.round]))
    if foreign:
        parser.error(f"{', '.join(foreign)} not in round {args.round}: {ROUNDS[args.round]}")
    screen = Screen()
    # a training driver is one across its stages, so a park stops all of them
    with nullcontext() if args.dry_run or args.park else screen.queue.driving():
        for candidate in args.candidates or ROUNDS[args.round]:
            for seed in args.seeds:
                mark, how = MARKS[args.round], (args.dry_run, args.park)
                reading = args.round in PAD_ENTERS_ROUNDS
                if candidate in DISTILLED:
                    going = screen.distilled(candidate, seed, mark, reading, *how)
                else:
                    going = screen.single(candidate, seed, mark, *how, reading=reading)
                if not going:
                    break
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
