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
checkpoint, metrics, config, wall time). A
candidate's runs on one seed (its pipeline) share BUDGET_SECONDS of wall time, every stage
counted: a run still training when its pipeline's launches reach it is stopped there and kept as
it is. The distilled candidate trains one teacher per kind, gives a group its teacher missed its
own teacher on the next seed (once), then distils every group's teacher into one student; the
candidate is judged on its last run (the student). A single-run candidate whose kept run misses
its round's mark (screen_rule.MARKS) is not run on the seeds after it.
"""

from __future__ import annotations

import argparse
import json
import sys
from contextlib import nullcontext
from pathlib import Path

from screen_rule import LEARNED, MARKS, last_window, passes

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, group_name
from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE
from realikea.training.queue import QueuedRun, RunQueue, keep_run

HERE = Path(__file__).resolve().parent
KEPT = HERE / "results/screen"
PARKED = HERE / "results/screen_parked"
WORK = WORKSPACE / "outputs/generalist_screen"
SEEDS = (20, 21)
BUDGET_SECONDS = 2 * 3600
COMMON = ("logger=none",)
# round 1 ran on python train.py's defaults of its day: the library's draw, CoACD, normal and the
# single-task agent (the library draw's default became agent=multitask, round 1's adopted
# group_ppo, after it); later rounds run on the defaults round 1 left
ROUND_1 = ("agent=ppo",)
AJAR_FP_DOORS = (
    "+task.ajar_share=0.3",
    "+task.ajar_groups=[finger_pull_door]",
    "+task.ajar_range=[0.4,1.0]",
)
SINGLE_RUN = {  # name -> (overrides, iterations)
    "group_ppo": (
        (
            *ROUND_1,
            "+agent.group_advantages=true",
            "agent.algorithm.schedule=fixed",
            "agent.algorithm.learning_rate=3e-4",
            "agent.num_steps_per_env=48",
        ),
        1500,
    ),
    "pregrasp": (
        (
            *ROUND_1,
            "+task.pregrasp_share=0.3",
            "+task.pregrasp_groups=[knob_door,two_point_door,finger_pull_door]",
        ),
        1500,
    ),
    "fp_pregrasp": (
        ("+task.pregrasp_share=0.5", "+task.pregrasp_groups=[finger_pull_door]"),
        1500,
    ),
    # the opening paid up to 1.25 x the success threshold (realikea/rewards/gated.py)
    "open_margin": (("task.reward.open_target=1.25",), 1500),
    # open jaws paid only before the episode's first grasp (realikea/rewards/gated.py)
    "hold_grasp": (("task.reward.reopen_bonus=false",), 1500),
    # every 10 iterations each env takes its group's next configuration
    # (realikea/training/rotating_draw.py): a group trains on all of its configurations
    "rotate": (("asset.rotate_every=10",), 1500),
    # rotate's draw, and 0.3 of the finger-pull door episodes start with the door ajar at 0.4-1.0
    # of the success mark, the hand at home (realikea/tasks/start_state.py)
    "rotate_ajar": (("asset.rotate_every=10", *AJAR_FP_DOORS), 1500),
}
# teachers: fixed poses to 200, then randomized (as the door specialists: 300 of 600); the
# student on randomized poses throughout (its teachers have learned them)
TEACHER_ITERATIONS, TEACHER_SWITCH, STUDENT_ITERATIONS = 400, 200, 200
ROUNDS = {
    1: ("group_ppo", "pregrasp", "distilled"),
    2: ("fp_pregrasp",),
    3: ("open_margin",),
    4: ("hold_grasp",),
    5: ("rotate",),
    6: ("rotate_ajar",),
}
CANDIDATES = tuple(c for candidates in ROUNDS.values() for c in candidates)


def run_name(candidate: str, seed: int, stage: str = "") -> str:
    return f"{candidate}_s{seed}" + (f"/{stage}" if stage else "")


def single_run(candidate: str, seed: int) -> QueuedRun:
    overrides, iterations = SINGLE_RUN[candidate]
    return QueuedRun(
        run_name(candidate, seed),
        (*COMMON, *overrides, f"env.seed={seed}", f"agent.max_iterations={iterations}"),
        iterations,
    )


def teacher_run(seed: int, kind: str, category: str = "") -> QueuedRun:
    """The teacher of one kind's groups, or (`category`) the own teacher of a group its kind's
    teacher missed, trained on the next seed."""
    stage = f"teacher_{group_name(category, kind) if category else kind}"
    scope = (f"asset={category}",) if category else ()
    return QueuedRun(
        run_name("distilled", seed, stage),
        (*COMMON, *ROUND_1, *scope, f"asset.kind={kind}",
         f"env.seed={seed + 1 if category else seed}",
         f"agent.max_iterations={TEACHER_ITERATIONS}", f"dr.switch_iteration={TEACHER_SWITCH}"),
        TEACHER_ITERATIONS,
    )  # fmt: skip


def student_run(seed: int, teachers: dict[str, Path]) -> QueuedRun:
    listed = ", ".join(f"{group}: {path}" for group, path in teachers.items())
    return QueuedRun(
        run_name("distilled", seed, "student"),
        (*COMMON, *ROUND_1, f"distill.teachers={{{listed}}}", f"env.seed={seed}",
         f"agent.max_iterations={STUDENT_ITERATIONS}", "dr.switch_iteration=0"),
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
            lambda run, seconds: keep_run(work / run.name, kept / run.name, seconds),
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

    def single(self, candidate: str, seed: int, mark: float, dry_run: bool, park: bool) -> bool:
        """Train (or show or park) a single-run candidate on one seed; whether its seeds after
        this one still run (not once its kept run misses `mark` in some group)."""
        run = single_run(candidate, seed)
        self.stage([run], dry_run, park)
        if self.queue.kept(run) and not passes(last_window(self.kept_dir / run.name), mark):
            print(f"{run.name} misses {mark:g} in some group: {candidate} stops at this seed")
            return False
        return True

    def distilled(self, seed: int, dry_run: bool, park: bool) -> None:
        """Teachers per kind, a group's own teacher where its kind's missed it, the student
        (each stage once the one before is kept)."""
        kinds = {kind: teacher_run(seed, kind) for kind in BASE_KINDS}
        for run in kinds.values():
            if not self.stage([run], dry_run, park) and not (dry_run or park):
                return
        if not all(self.queue.kept(r) for r in kinds.values()):
            return  # shown or parked
        teachers = {}
        for kind, run in kinds.items():
            values = last_window(self.kept_dir / run.name)
            for category in CATEGORIES:
                group = group_name(category, kind)
                teachers[group] = run if (values[group] or 0.0) >= LEARNED else None
        for group in [g for g, run in teachers.items() if run is None]:
            category, kind = group.rsplit("_", 1)
            teachers[group] = teacher_run(seed, kind, category)
            if not self.stage([teachers[group]], dry_run, park):
                return
        paths = {g: checkpoints(self.kept_dir / r.name)[-1][1] for g, r in teachers.items()}
        self.stage([student_run(seed, paths)], dry_run, park)


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
                if candidate == "distilled":
                    screen.distilled(seed, args.dry_run, args.park)
                elif not screen.single(candidate, seed, MARKS[args.round], args.dry_run, args.park):
                    break
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
