"""Train the generalists on the gated reward, two at a time, resumable, and keep each
finished run in experiments/generalist/results/<recipe>/s<seed>/ (slim last checkpoint,
metrics, the launches' wall times, the Hydra config, the learning curve).

    python experiments/generalist/train_gated.py                      # every run not yet kept
    python experiments/generalist/train_gated.py --recipes hull_high --seeds 0 --dry-run
    python experiments/generalist/train_gated.py --recipes hull_high --seeds 0 --park  # into git

Recipes, each one training run (`pipeline=none`): `default` is `python train.py` of its day
(CoACD, normal, every category and kind, the single-task agent, 1,500 iterations); `hull_high`
the design card's `python train.py collision=hull resistance=high` of its day;
`default_doors2` the default with twice the draw's turns for door groups (`asset.group_weights`);
`default_follow` the default with a draw that follows training success
(`asset.follow_success`); `doors` door specialists (the default on doors only, 600 iterations);
`fp_doors_rotate` finger-pull door specialists taking turns over the group's configurations
(`asset.rotate_every`, 1,000 iterations); `knob_doors_rotate` knob doors' own teacher of the
screen's pipelines, and `knob_doors_fixed_lr` the same at a fixed learning rate (400 iterations).
Each run gets one env worker (two side by side on the 2 cores). Then evaluate each kept
checkpoint on the test parts with `evaluate.py` (and, for hull_high, also on its own geometry:
`evaluate.py CHECKPOINT hull_high/s0_own collision=hull --modes high`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from realikea.config import override_key
from realikea.files import WORKSPACE
from realikea.reports.learning_curve import plot_learning_curve
from realikea.training.queue import QueuedRun, RunQueue, keep_run

RESULTS = WORKSPACE / "experiments/generalist/results"
WORK = WORKSPACE / "outputs/generalist"
ITERATIONS = 1500  # the defaults' agent.max_iterations
# knob doors' own teacher as the screen's pipelines train it (every_stage and own_teachers of
# realikea/conf/pipeline/distilled.yaml and distilled_pairs_knob.yaml), but the seed
KNOB_TEACHER = [
    "agent=ppo",
    "asset.rotate_every=10",
    "asset=knob",
    "asset.kind=door",
    "agent.max_iterations=400",
    "dr.switch_iteration=200",
]
# every recipe was run, and stays, on the single-task agent (agent=ppo) as one run, the
# defaults of its day (python train.py now trains a pipeline: aims.py trains it)
RECIPES = {
    "default": ["agent=ppo"],
    "hull_high": ["agent=ppo", "collision=hull", "resistance=high"],
    # the default with each door group drawn twice as often (about 11 of the 64 envs, the others
    # 5-6): doors are learned last, or never, in the default's seeds
    "default_doors2": ["agent=ppo", "asset.group_weights={door:2}"],
    # the default with a draw that follows training success: every 50 iterations each group
    # below 0.5 success takes three turns of the draw for every one of the others
    "default_follow": ["agent=ppo", "asset.follow_success={every:50,below:0.5,weight:3}"],
    # door specialists: the default on doors only (the three categories, about 21 envs each),
    # 600 iterations, poses fixed to 300: whether doors are learned in every seed on their own
    "doors": [
        "agent=ppo",
        "asset.kind=door",
        "agent.max_iterations=600",
        "dr.switch_iteration=300",
    ],
    # finger-pull door specialists whose envs take turns over all 76 of the group's train
    # configurations every 10 iterations, 1,000 iterations, poses fixed to 500: how far a policy
    # given nothing else to learn opens that group (README, "A finger-pull door specialist")
    "fp_doors_rotate": [
        "agent=ppo",
        "asset=finger_pull",
        "asset.kind=door",
        "asset.rotate_every=10",
        "agent.max_iterations=1000",
        "dr.switch_iteration=500",
    ],
    # knob doors' own teacher of the screen's rounds 9-10 (realikea/conf/pipeline/), run on its
    # own: how often a seed learns it (README, "A knob-door teacher over seeds")
    "knob_doors_rotate": KNOB_TEACHER,
    # the same at a fixed rate of 3e-4, the adopted multi-task agent's, not the adaptive one
    "knob_doors_fixed_lr": [
        *KNOB_TEACHER,
        "agent.algorithm.schedule=fixed",
        "agent.algorithm.learning_rate=3e-4",
    ],
}


def generalist_run(recipe: str, seed: int) -> QueuedRun:
    # checkpoints every 25 iterations: a session stopped mid-run loses little when it resumes
    overrides = (*RECIPES[recipe], "pipeline=none", f"env.seed={seed}", "logger=none",
                 "env.num_workers=1", "agent.save_interval=25")  # fmt: skip
    return QueuedRun(f"{recipe}_s{seed}", overrides, recipe_length(RECIPES[recipe]))


def recipe_length(recipe: list[str]) -> int:
    """The recipe's own agent.max_iterations, else the defaults' (ITERATIONS)."""
    given = [o.split("=", 1)[1] for o in recipe if override_key(o) == "agent.max_iterations"]
    return int(given[-1]) if given else ITERATIONS


def kept_dir(run: QueuedRun) -> Path:
    recipe, seed = run.name.rsplit("_", 1)
    return RESULTS / recipe / seed


def last_checkpoint(run: QueuedRun) -> str:
    return f"model_{run.iterations - 1}.pt"


def keep(run: QueuedRun, seconds: list[float]) -> Path:
    """Keep the run (`keep_run`) and plot its learning curve beside it."""
    kept = keep_run(WORK / run.name, kept_dir(run), seconds)
    plot_learning_curve(kept)
    return kept


def kept(run: QueuedRun) -> bool:
    return (kept_dir(run) / last_checkpoint(run)).is_file()


# a session's stopped runs, for a later machine to resume (`--park`; in git)
PARKED = RESULTS / "gated_parked"
QUEUE = RunQueue(WORK, last_checkpoint, keep, kept, parked=PARKED)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--recipes", nargs="+", choices=list(RECIPES), default=["default", "hull_high"]
    )
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1])
    parser.add_argument("--jobs", type=int, default=2, help="runs side by side (2 cores: 2)")
    parser.add_argument("--dry-run", action="store_true", help="print the commands only")
    parser.add_argument("--park", action="store_true", help="stop at next checkpoints; copy to git")
    args = parser.parse_args()
    if any(s < 0 for s in args.seeds):
        parser.error(f"seeds must be >= 0, got {args.seeds}")
    runs = [generalist_run(r, s) for s in args.seeds for r in args.recipes]
    return QUEUE.serve(runs, args.jobs, dry_run=args.dry_run, park=args.park)


if __name__ == "__main__":
    sys.exit(main())
