"""`hook_oracle`'s loop on each two-point test part, for one gripper preset: whether it opens the
drawer, and the jaws' opening (fraction of the stroke) at the end of the close and one step into
the pull. A jump between the two is the bar pushing the jaws apart. Prints a markdown table.

    python experiments/kitchen/loop_aperture.py --gripper menagerie_servo --contact pyramidal

Kitchen, high resistance, randomized poses (draws `--seeds`), two drawer bases.
"""

from __future__ import annotations

import argparse
import math

from realikea.assets.catalog import Catalog
from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.policies.registry import make_policy
from realikea.policies.rollout import episode
from realikea.tasks.open_task import OpenTask


def loop_episode(cfg, seed: int) -> tuple[str, float, float]:
    """One episode: its outcome and the aperture at the end of the close and at the pull's
    first step."""
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=seed)
    policy = make_policy(cfg)
    closed = pulled = float("nan")
    for result in episode(task, policy):
        info = result.info  # the last step's once the loop ends
        # hook_oracle's loop: "close" on the bar, then "pull"
        step = policy.step(0)
        if step == "close":
            closed = task.aperture
        elif step == "pull" and math.isnan(pulled):  # the first step of the pull
            pulled = task.aperture
    return info["outcome"], closed, pulled


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--gripper", default="franka_hand")
    parser.add_argument("--contact", default="elliptic")
    parser.add_argument("--bases", nargs="+", default=["drawer_w40_h20", "drawer_w80_h40"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1])
    args = parser.parse_args()
    catalog = Catalog.load()
    parts = catalog.parts_of_split(catalog.parts_in("two_point"), "test")
    print(f"`{args.gripper}` / {args.contact}, high, kitchen, seeds {args.seeds}\n")
    print("| part | base | seed | outcome | aperture closed | aperture pulling |")
    print("|---|---|---:|---|---:|---:|")
    for part in parts:
        for base in args.bases:
            cfg = load_config(
                [f"asset.part={part.id}", f"asset.base={base}", "dr=randomized",
                 "policy=hook_oracle", "resistance=high", "scene=kitchen",
                 f"gripper={args.gripper}", f"contact={args.contact}"],
                "eval",
            )  # fmt: skip
            for seed in args.seeds:
                outcome, closed, pulled = loop_episode(cfg, seed)
                print(f"| {part.id} | {base} | {seed} | {outcome} | {closed:.3f} | {pulled:.3f} |")


if __name__ == "__main__":
    main()
