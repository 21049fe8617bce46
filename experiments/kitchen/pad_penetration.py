"""Whether a scripted catch bears on the part or on the contact model's softness: one
`hook_oracle` episode per configuration (kitchen, high, fixed pose), with the deepest
pad-to-part penetration and the normal force the pads carry while the front opens. Prints a
markdown table.

    python experiments/kitchen/pad_penetration.py fp_edge_64__drawer_w60_h10 [CONFIG ...]
"""

from __future__ import annotations

import argparse

import mujoco
import numpy as np

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.policies.registry import make_policy
from realikea.policies.rollout import episode
from realikea.sim.robot import PAD_GEOMS
from realikea.sim.scene import PART_BODY, subtree_geoms
from realikea.tasks.open_task import OpenTask


def pad_contacts(model, data, pads: set[int], part: set[int]) -> tuple[float, float]:
    """(deepest penetration in m, summed normal force in N) of the pads' contacts with the part."""
    deepest, force, wrench = 0.0, 0.0, np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        if {contact.geom1, contact.geom2} & pads and {contact.geom1, contact.geom2} & part:
            deepest = min(deepest, contact.dist)
            mujoco.mj_contactForce(model, data, i, wrench)
            force += abs(wrench[0])
    return deepest, force


def measure(config_id: str) -> dict:
    part_id, _, base_id = config_id.partition("__")
    cfg = load_config(
        [f"asset.part={part_id}", f"asset.base={base_id}", "dr=fixed", "policy=hook_oracle",
         "resistance=high", "scene=kitchen", "contacts.log=true"],
        "eval",
    )  # fmt: skip
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    model, data = task.model, task.data
    pads = {model.geom(name).id for name in PAD_GEOMS}
    part = set(subtree_geoms(model, model.body(PART_BODY).id))
    policy = make_policy(cfg)
    deepest, forces = 0.0, []
    for result in episode(task, policy):
        info = result.info  # the last step's once the loop ends
        depth, force = pad_contacts(model, data, pads, part)
        deepest = min(deepest, depth)
        if force > 0 and task.opening > 0.005:  # the front moving on the pads
            forces.append(force)
    return {
        "outcome": info["outcome"], "strategy": info["strategy"],
        "opening": task.opening, "deepest_mm": -1000 * deepest,
        "force": (min(forces), max(forces)) if forces else (0.0, 0.0),
    }  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("configs", nargs="+", help="configuration ids <part>__<base>")
    args = parser.parse_args()
    print(
        "| configuration | outcome | strategy | opening | deepest (mm) | pads' normal force (N) |"
    )
    print("|---|---|---|---:|---:|---|")
    for config_id in args.configs:
        m = measure(config_id)
        lo, hi = m["force"]
        print(f"| {config_id} | {m['outcome']} | {m['strategy']} | {m['opening']:.3f} | "
              f"{m['deepest_mm']:.2f} | {lo:.1f}–{hi:.1f} |")  # fmt: skip


if __name__ == "__main__":
    main()
