"""The reward screen: train each recipe on four cells where the appendix recipe rarely learned,
with both collision sources and several seeds, two runs at a time; keep each finished run in
experiments/reward_screen/results/runs/NAME/ (its Hydra config, metrics, slim last checkpoint,
wall time).

    python experiments/reward_screen/screen.py                  # every run not yet kept
    python experiments/reward_screen/screen.py --recipes gated --cells knob_smooth --seeds 0 1
    python experiments/reward_screen/screen.py --dry-run        # the commands and their state

Drawers in the kitchen, train parts, 400 iterations with fixed poses to 200 (then randomized),
one env worker a run. NAME is <recipe>_<collision>_<cell>_s<seed>. A run stops once it has
learned and holds it on randomized poses (`holds_after_switch`): its outcome is then decided, and
the rest of its schedule would only refine the kept checkpoint. The same command resumes a
stopped run from its last checkpoint (realikea/training/queue.py). The table and the curves:
`python experiments/reward_screen/report.py`.
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import numpy as np

from realikea.files import WORKSPACE
from realikea.runs.curves import SUCCESS_WINDOW, trailing_mean
from realikea.sources import SOURCES
from realikea.training.metrics import read_metrics
from realikea.training.queue import QueuedRun, RunQueue, keep_run

KEPT = WORKSPACE / "experiments/reward_screen/results/runs"
WORK = WORKSPACE / "outputs/reward_screen"
ITERATIONS = 400
SWITCH = 200  # fixed poses before this iteration, randomized from it
LEARNED = 0.5  # training success, averaged over SUCCESS_WINDOW iterations, that counts as learned
# four cells where the appendix recipe learned in few runs (the fidelity grid, 900 iterations,
# full 20-iteration windows: two-point x smooth and knob x high 2 of 6, knob and finger pull x
# smooth 3 of 6; finger pull x high, 2 of 6, was not screened): (category, training resistance)
CELLS = {
    "two_point_smooth": ("two_point", "smooth"),
    "knob_smooth": ("knob", "smooth"),
    "finger_pull_smooth": ("finger_pull", "smooth"),
    "knob_high": ("knob", "high"),
}
COLLISIONS = SOURCES
# `gated`'s opening weights before the screen made gated_pull_rate's its defaults: every recipe
# pins them, so each names the reward its kept runs were trained on
GATED_AS_SCREENED = [
    "task/reward=gated",
    "task.reward.keep_opening=false",
    "task.reward.w_progress=40.0",
    "task.reward.success_bonus=20.0",
    "task.reward.w_rate=0.0",
]


def gated(*changes: str) -> list[str]:
    """The overrides of `gated` as screened with `changes` (key=value) made to it."""
    changed = {change.split("=")[0] for change in changes}
    return [o for o in GATED_AS_SCREENED if o.split("=")[0] not in changed] + list(changes)


# recipe -> the train.py overrides that make it (the rest: the defaults)
RECIPES = {
    "gated": gated(),
    # the fidelity grid's recipe: the appendix reward with w_open2 = 0, every env in lockstep
    "appendix": [
        "task/reward=appendix", "task.reward.w_open2=0.0", "agent.init_at_random_ep_len=false",
    ],
    # one change of the gated recipe undone at a time
    "gated_lockstep": gated("agent.init_at_random_ep_len=false"),
    "gated_unscaled": gated("task.reward.scale=1.0"),
    # the gated recipe paying, in stage 3, the jaws centred on the handle (w_center): two of
    # its runs ended straddling the handle without gripping it
    "gated_centred": gated("task.reward.w_center=5.0"),
    # the gated recipe with a cost on pressing the closed front shut (w_push): the policies of
    # the runs that did not learn press it (over 50 N on 0.60-0.97 of steps, pressing.md)
    "gated_push": gated("task.reward.w_push=40.0"),
    # and a cost on the policy's action beyond its clip (w_bound): under gated_push the hull
    # two-point s1 run held its pinch without opening, its vertical command's mean past the clip
    "gated_push_bound": gated(
        "task.reward.w_push=40.0", "task.reward.w_bound=5.0",
    ),
    # and the opening paid once the episode has grasped, grasp held or not (keep_opening): its
    # policy, made to pull, opened 15-22 cm and lost the pinch on the way, which paid nothing
    "gated_keep": gated(
        "task.reward.w_push=40.0", "task.reward.w_bound=5.0",
        "task.reward.keep_opening=true",
    ),
    # and stage 3 only with the handle site within 12 mm of the pads' line (the pad's half
    # length, 9 mm, plus 3): the seed-1 runs ended most episodes in stage 3 for 100-200
    # iterations before a grasp, and at 25 mm jaws short of the handle straddle it
    "gated_tight": gated(
        "task.reward.w_push=40.0", "task.reward.w_bound=5.0",
        "task.reward.keep_opening=true", "task.reward.straddle_radius=0.012",
    ),
    # gated_tight without w_bound: costing the sampled action past the clip also costs its
    # spread, and the runs with w_bound had their action std at 0.23-0.26 by iteration 120
    # (0.45-0.77 without it)
    "gated_tight_unbound": gated(
        "task.reward.w_push=40.0", "task.reward.keep_opening=true",
        "task.reward.straddle_radius=0.012",
    ),
    # gated_push with a floor under the action std: the runs that held a grasp without pulling
    # ended at a std of 0.18-0.30 (exploration.md)
    "gated_push_floor": gated("task.reward.w_push=40.0", "agent.min_std=0.4"),
    # gated with the opening kept from the first grasp on and paid three times as much: a pull
    # that opens 5 cm and slips then earns more a step (stage 2 or 3, 17-27, plus 30 for the
    # opening) than holding the grasp still (about 40); at w_progress 40 it earns 27-37
    "gated_pull": gated(
        "task.reward.keep_opening=true", "task.reward.w_progress=120.0",
        "task.reward.success_bonus=60.0",
    ),
    # gated_pull with a floor under the action std, tried on the CoACD knob x smooth s1 run that
    # ended straddling the knob (stage 3 in 0.61 of its last 20 iterations): its std never fell
    # below 0.58, so the floor never engaged (every logged value as gated_pull's to 164)
    "gated_pull_floor": gated(
        "task.reward.keep_opening=true", "task.reward.w_progress=120.0",
        "task.reward.success_bonus=60.0", "agent.min_std=0.4",
    ),
    # gated_pull paying stage 3 the approach to t2 (w_app3 = w_hold): the knob runs that did not
    # learn straddle the knob at one finger's tip, short of t2, where stage 3 paid nothing more
    "gated_pull_app3": gated(
        "task.reward.keep_opening=true", "task.reward.w_progress=120.0",
        "task.reward.success_bonus=60.0", "task.reward.w_app3=2.0",
    ),
    # gated_pull paying the opening's increase as well as its level (w_rate = 10 x w_progress:
    # a step's pull is paid at once what the level pays for it over the next 10 steps): its knob
    # runs that did not learn held grasps that open the drawer when made to pull, yet pulled
    # slowly (forced_pull.py)
    "gated_pull_rate": gated(
        "task.reward.keep_opening=true", "task.reward.w_progress=120.0",
        "task.reward.success_bonus=60.0", "task.reward.w_rate=1200.0",
    ),
    # gated_pull_rate with w_app3 = w_hold: its CoACD knob s4 run ended straddling the knob
    # (stage 3 in 0.65 of its last episodes), the pattern w_app3 was built for
    "gated_pull_rate_app3": gated(
        "task.reward.keep_opening=true", "task.reward.w_progress=120.0",
        "task.reward.success_bonus=60.0", "task.reward.w_rate=1200.0", "task.reward.w_app3=2.0",
    ),
}  # fmt: skip
# the kitchen's robot as every screen run had it: the arm 0.80 m below every handle (the finger
# pulls' own placement, scene.robot.placements, came after the screen's first runs)
COMMON = [
    "asset.kind=drawer", "scene=kitchen", "scene.robot.placements=[]", "logger=none",
    "env.num_workers=1",
    f"agent.max_iterations={ITERATIONS}", "agent.save_interval=10", "dr=two_phase",
    f"dr.switch_iteration={SWITCH}",
]  # fmt: skip


def screen_run(recipe: str, collision: str, cell: str, seed: int) -> QueuedRun:
    category, resistance = CELLS[cell]
    overrides = [*RECIPES[recipe], f"collision={collision}", f"asset={category}"]
    overrides += [f"resistance={resistance}", f"env.seed={seed}", *COMMON]
    return QueuedRun(f"{recipe}_{collision}_{cell}_s{seed}", tuple(overrides), ITERATIONS)


def last_checkpoint(run: QueuedRun) -> str:
    return f"model_{run.iterations - 1}.pt"


def keep(run: QueuedRun, seconds: list[float]) -> Path:
    return keep_run(WORK / run.name, KEPT / run.name, seconds)


def kept(run: QueuedRun) -> bool:
    return (KEPT / run.name / "wall.json").is_file()  # keep_run writes the folder whole


def holds_after_switch(run: QueuedRun) -> bool:
    """Whether the run's training success, averaged over SUCCESS_WINDOW iterations all on
    randomized poses, has reached LEARNED: it has learned (the report's criterion) and holds it
    off the fixed poses."""
    metrics = WORK / run.name / "metrics.csv"
    if not metrics.is_file():
        return False
    its, values = read_metrics(metrics.parent).get("/episode/success", ([], []))
    by_iteration = dict(zip(its, values, strict=True))  # a resumed launch's rows replace earlier
    randomized = sorted(it for it in by_iteration if it >= SWITCH)
    _, means = trailing_mean(randomized, [by_iteration[it] for it in randomized], SUCCESS_WINDOW)
    return bool(np.any(means >= LEARNED))


QUEUE = RunQueue(WORK, last_checkpoint, keep, kept, stop_early=holds_after_switch)


def planned(args: argparse.Namespace) -> list[QueuedRun]:
    """The runs the arguments select, seed by seed (every cell has a seed before any has two)."""
    for name, given, known in (
        ("recipe", args.recipes, RECIPES),
        ("cell", args.cells, CELLS),
        ("collision", args.collisions, COLLISIONS),
    ):
        bad = [v for v in given if v not in known]
        if bad:
            raise ValueError(f"unknown {name} {', '.join(bad)}: use {', '.join(known)}")
    if any(s < 0 for s in args.seeds):
        raise ValueError(f"seeds must be >= 0, got {args.seeds}")
    return [
        screen_run(recipe, collision, cell, seed)
        for recipe in args.recipes
        for seed, cell, collision in itertools.product(args.seeds, args.cells, args.collisions)
    ]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--recipes", nargs="+", default=["gated"])
    parser.add_argument("--cells", nargs="+", default=list(CELLS))
    parser.add_argument("--collisions", nargs="+", default=list(COLLISIONS))
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2, 3, 4])
    parser.add_argument("--jobs", type=int, default=2, help="runs side by side (2 cores: 2)")
    parser.add_argument("--dry-run", action="store_true", help="print the commands only")
    args = parser.parse_args()
    try:
        runs = planned(args)
    except ValueError as err:
        parser.error(str(err))
    if args.dry_run:
        QUEUE.show(runs)
        return 0
    return QUEUE.run_all(runs, args.jobs)


if __name__ == "__main__":
    sys.exit(main())
