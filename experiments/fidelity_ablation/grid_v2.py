"""The fidelity grid on today's recipe (v2), on seeds the project never used: collision source x
training resistance x category, drawers, kitchen, train parts; each run evaluated at its last
checkpoint on the test parts (CoACD geometry) in smooth, normal and high.

    python experiments/fidelity_ablation/grid_v2.py --freeze   # once, before any run: recipe.yaml
    python experiments/fidelity_ablation/grid_v2.py --dry-run  # the runs, their state, commands
    python experiments/fidelity_ablation/grid_v2.py            # every run not kept, two at a time
    python experiments/fidelity_ablation/grid_v2.py --park     # stop at next checkpoints, into git

The recipe is frozen in results/grid_v2/recipe.yaml (`--freeze` writes today's resolved task,
agent, scene, sim, gripper, contact and pose ranges there, and refuses to overwrite it). Every
run composes it as a config group from this folder's results/ (`hydra.searchpath`,
`+grid_v2=recipe`), so later changes to the defaults do not change the grid's runs. Runs train in
outputs/grid_v2/NAME, resume from their last checkpoint, and are kept in results/grid_v2/NAME
(grid_runs.py). The recipe is merged over the defaults, so a key a later
default adds to a pinned group would reach the grid's runs: tests/test_grid_v2.py then fails.
Such a key must mean the old behaviour when absent, and the runs delete it (`~agent.new_key` in
`grid_v2_run`'s overrides).
Seeds, schedule, checkpoint rule and the registered comparisons: README.md, "The grid on today's
recipe".
"""

from __future__ import annotations

import argparse
import itertools
import sys

from grid_runs import GridRun, grid_queue
from omegaconf import OmegaConf

from realikea.config import load_config
from realikea.files import WORKSPACE

RESULTS = WORKSPACE / "experiments/fidelity_ablation/results"
KEPT = RESULTS / "grid_v2"
RECIPE = KEPT / "recipe.yaml"
WORK = WORKSPACE / "outputs/grid_v2"
PARKED = RESULTS / "grid_v2_parked"  # stopped runs' resumable state, for the next machine
RECIPE_OVERRIDES = (
    f"hydra.searchpath=[file://{RESULTS.relative_to(WORKSPACE)}]",
    "+grid_v2=recipe",
)
COLLISIONS = ("coacd", "hull")
RESISTANCES = ("high", "smooth", "normal")
CATEGORIES = ("two_point", "knob", "finger_pull")
SEEDS = (100, 101, 102)
FIVE_SEEDS = (100, 101, 102, 103, 104)  # the cells of the registered comparisons
FIVE_SEED_CELLS = {("two_point", "smooth"), ("two_point", "high"), ("knob", "high")}
ITERATIONS, SWITCH = 600, 300  # fixed poses to SWITCH, then randomized
PINNED = ("task", "agent", "scene", "sim", "gripper", "contact")  # whole groups the recipe pins
PINNED_DR = ("handle", "base")  # the pose ranges; the mode is the run's (two_phase) or eval's
# what every run sets besides its recipe (not part of the science: how it runs here)
RUN_SETTINGS = {
    "logger": {"backend": "none"},
    "env": {"num_workers": 1},  # two runs side by side on 2 cores
    "train": {
        "eval_after": {
            "collision": "coacd", "episodes": 50, "resistances": ["smooth", "normal", "high"],
            "dr": "randomized", "seed": 1000, "split": "test",
        },
    },
}  # fmt: skip
# task settings added after the freeze, at the values that reproduce what the frozen recipe
# trained: every run composes them from the defaults, which the recipe file predates
ADDED_AFTER_FREEZE = {
    # no door seen as its hinge twin (realikea/tasks/mirror.py), as every run before it trained
    "task": {"reward": {"open_target": 1.0, "reopen_bonus": True}, "mirror_doors": False},
    "agent": {"max_std": None},  # no ceiling on the action std, as every run before it trained
}


def recipe_of(cfg) -> dict:
    """The part of a composed config the grid pins: PINNED groups, the pose ranges, the settings."""
    recipe = {group: OmegaConf.to_container(cfg[group], resolve=True) for group in PINNED}
    recipe["dr"] = {k: OmegaConf.to_container(cfg.dr[k], resolve=True) for k in PINNED_DR}
    recipe["agent"]["max_iterations"] = ITERATIONS
    return {**recipe, **RUN_SETTINGS}


def frozen_recipe() -> dict:
    """The frozen recipe, with the settings added after it at their reproducing values."""
    merged = OmegaConf.merge(OmegaConf.load(RECIPE), ADDED_AFTER_FREEZE)
    return OmegaConf.to_container(merged)


def freeze() -> None:
    """Write today's defaults as the recipe, once."""
    if RECIPE.exists():
        raise SystemExit(f"{RECIPE} exists: the recipe is frozen (delete it only before any run)")
    header = "# @package _global_\n# The fidelity grid v2's frozen recipe (grid_v2.py --freeze)\n"
    body = OmegaConf.to_yaml(OmegaConf.create(recipe_of(load_config([]))))
    RECIPE.parent.mkdir(parents=True, exist_ok=True)
    RECIPE.write_text(header + body)


def seeds_of(category: str, resistance: str) -> tuple[int, ...]:
    return FIVE_SEEDS if (category, resistance) in FIVE_SEED_CELLS else SEEDS


def grid_v2_run(collision: str, resistance: str, category: str, seed: int) -> GridRun:
    overrides = [
        *RECIPE_OVERRIDES, f"collision={collision}", f"resistance={resistance}",
        f"asset={category}", "asset.kind=drawer", "asset.split=train", "scene=kitchen",
        "dr=two_phase", f"dr.switch_iteration={SWITCH}", f"env.seed={seed}", "env.num_envs=64",
    ]  # fmt: skip
    name = f"{collision}_{resistance}_{category}_s{seed}"
    return GridRun(name, tuple(overrides), ITERATIONS, collision, resistance, category, seed)


def planned(collisions=COLLISIONS, resistances=RESISTANCES, categories=CATEGORIES) -> list[GridRun]:
    """The grid's runs, seed by seed (every cell has its first seed before any has its second)."""
    cells = list(itertools.product(categories, resistances, collisions))
    return [
        grid_v2_run(collision, resistance, category, seed)
        for seed in FIVE_SEEDS
        for category, resistance, collision in cells
        if seed in seeds_of(category, resistance)
    ]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--collisions", nargs="+", choices=COLLISIONS, default=list(COLLISIONS))
    parser.add_argument("--resistances", nargs="+", choices=RESISTANCES, default=list(RESISTANCES))
    parser.add_argument("--categories", nargs="+", choices=CATEGORIES, default=list(CATEGORIES))
    parser.add_argument("--jobs", type=int, default=2, help="runs side by side (2 cores: 2)")
    parser.add_argument("--dry-run", action="store_true", help="print the commands only")
    parser.add_argument("--freeze", action="store_true", help="write recipe.yaml from the defaults")
    parser.add_argument("--park", action="store_true", help="stop at next checkpoints; copy to git")
    args = parser.parse_args()
    if args.freeze:
        freeze()
        return 0
    if not RECIPE.is_file():
        parser.error(f"no frozen recipe at {RECIPE}: run --freeze first")
    runs = planned(args.collisions, args.resistances, args.categories)
    queue = grid_queue(WORK, KEPT)
    queue.parked = PARKED
    return queue.serve(runs, args.jobs, args.dry_run, args.park)


if __name__ == "__main__":
    sys.exit(main())
