"""What bounds `hook_oracle` on a finger-pull door: one episode per configuration (kitchen, high,
fixed pose), with the arm joint nearest its position limit when the pad reaches the lip, the
share of pull steps in which an arm joint's actuator is at its torque limit (and which joint),
and the door's final angle. `--set` adds a Hydra override (`--set 'scene.robot.placements=[]'`:
the hand not turned). Prints a markdown table.

    python experiments/kitchen/wrist_load.py fp_lip_36__door_left_w40_h80 [CONFIG ...]
"""

from __future__ import annotations

import argparse
from collections import Counter

import numpy as np

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.policies.registry import make_policy
from realikea.policies.rollout import episode
from realikea.sim.robot import joint_limits
from realikea.sim.scene import ARM_ACTUATORS, ARM_JOINTS
from realikea.tasks.open_task import OpenTask

SATURATED = 0.99  # share of an actuator's force range that counts as at its limit


def measure(config_id: str, overrides: list[str]) -> dict:
    part_id, _, base_id = config_id.partition("__")
    cfg = load_config(
        [f"asset.part={part_id}", f"asset.base={base_id}", "dr=fixed", "policy=hook_oracle",
         "resistance=high", "scene=kitchen", "contacts.log=true", *overrides],
        "eval",
    )  # fmt: skip
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    model, data = task.model, task.data
    lo, hi = joint_limits().T
    limit = np.array([model.actuator(name).forcerange[1] for name in ARM_ACTUATORS])
    policy = make_policy(cfg)
    margin, saturated, pulling = None, Counter(), 0
    for result in episode(task, policy):
        info = result.info  # the last step's once the loop ends
        q = np.array([data.joint(name).qpos[0] for name in ARM_JOINTS])
        # hook_oracle's: "catch" sets the pad on the edge
        step = policy.step(0)
        if step == "catch":  # its last step there counts
            margin = np.minimum(q - lo, hi - q)
        if step == "pull":
            pulling += 1
            force = np.abs([data.actuator(name).force[0] for name in ARM_ACTUATORS])
            saturated.update(int(j) + 1 for j in np.flatnonzero(force >= SATURATED * limit))
    nearest = int(np.argmin(margin)) + 1 if margin is not None else 0
    return {
        "strategy": info["strategy"], "opening": task.opening,
        "nearest": (nearest, float(margin.min()) if margin is not None else float("nan")),
        "saturated": {j: n / max(pulling, 1) for j, n in sorted(saturated.items())},
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("configs", nargs="+", help="configuration ids <part>__<base>")
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        help="a Hydra override (repeatable)")  # fmt: skip
    args = parser.parse_args()
    overrides = args.overrides
    print(f"overrides: {' '.join(overrides) or 'none'}\n")
    print("| configuration | strategy | door (rad) | joint nearest its limit at the catch (rad "
          "left) | pull steps with a joint at its torque limit |")  # fmt: skip
    print("|---|---|---:|---|---|")
    for config_id in args.configs:
        m = measure(config_id, overrides)
        joint, left = m["nearest"]
        held = ", ".join(f"joint {j}: {share:.2f}" for j, share in m["saturated"].items())
        print(f"| {config_id} | {m['strategy']} | {m['opening']:.2f} | joint {joint} ({left:.2f}) "
              f"| {held or 'none'} |")  # fmt: skip


if __name__ == "__main__":
    main()
