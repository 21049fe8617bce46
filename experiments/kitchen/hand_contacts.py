"""What `hook_oracle`'s hand runs into where it falls short: `realikea eval`'s own episodes of
one category x kind (test parts, kitchen, high, randomized poses, `env.seed=0`; the eval's env
pool, in one process), each failed or partial one, or successful but not labelled hook or
lever, with its configuration, its label and friction share, the oracle's note if it planned
nothing, the front's final opening, and the first geoms off the part the hand or its fingers
touched (`front` for the moving panel around the part, else the kitchen's boards) with the
control step. Prints a markdown table and the count per first contact.

    python experiments/kitchen/hand_contacts.py knob drawer [--episodes 50] [--set OVERRIDE]
"""

from __future__ import annotations

import argparse
from collections import Counter

from realikea.eval.setup import eval_setup, evaluate
from realikea.sim.robot import FINGER_BODIES, HAND_BODY
from realikea.sim.scene import FRONT_BODY, subtree_geoms
from realikea.tasks.contract import StepResult
from realikea.tasks.open_task import OpenTask

FORM_CLOSURE = ("hook", "lever")  # the labels the aim credits


class HandContactTask(OpenTask):
    """An `OpenTask` whose episode record names the first geoms off the part the hand touched
    (`first_off_part`: names and control step, or None) and its configuration."""

    episode_keys = (*OpenTask.episode_keys, "first_off_part", "config_id")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        model = self.model
        self._hand = {model.body(name).id for name in (HAND_BODY, *FINGER_BODIES)}
        self._front_geoms = set(subtree_geoms(model, model.body(FRONT_BODY).id))  # the part's too

    def reset(self):
        self._first, self._t = None, 0
        return super().reset()

    def evaluate(self, ik_ok: bool) -> StepResult:
        result = super().evaluate(ik_ok)
        if self._first is None:
            touched = self._off_part()
            if touched:
                self._first = (sorted(touched), self._t)
        self._t += 1
        if result.terminated or result.truncated:
            result.info.update(first_off_part=self._first, config_id=self.config_id)
        return result

    def _off_part(self) -> set[str]:
        """Names of the geoms off the part touching the hand now (`front` for the moving
        front's own)."""
        model, data, names = self.model, self.data, set()
        for contact in data.contact[: data.ncon]:
            g1, g2 = int(contact.geom1), int(contact.geom2)
            in1, in2 = model.geom_bodyid[g1] in self._hand, model.geom_bodyid[g2] in self._hand
            other = g2 if in1 else g1
            if in1 == in2 or model.geom_bodyid[other] == self._part:
                continue
            name = model.geom(other).name or "unnamed"
            names.add("front" if other in self._front_geoms else name.split("/")[-1])
        return names


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("category", choices=["two_point", "knob", "finger_pull"])
    parser.add_argument("kind", choices=["drawer", "door", "flap"])
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        help="a Hydra override (repeatable)")  # fmt: skip
    args = parser.parse_args()
    overrides = [
        "policy=hook_oracle", f"asset={args.category}", f"asset.kind={args.kind}",
        "asset.split=test", "resistance=high", "dr=randomized", f"episodes={args.episodes}",
        "scene=kitchen", "env.num_workers=0", *args.overrides,
    ]  # fmt: skip
    cfg, policy = eval_setup(overrides)
    episodes = evaluate(cfg, policy, progress=False, task_factory=HandContactTask).episodes
    outcomes = Counter(e.get("outcome", "fail") for e in episodes)
    print(f"`realikea eval {' '.join(overrides)}`: "
          + ", ".join(f"{o} {n}" for o, n in sorted(outcomes.items())) + "\n")  # fmt: skip
    print("| configuration | env | outcome | label (friction share) | opening | first contact off "
          "the part (step) |")  # fmt: skip
    print("|---|---:|---|---|---:|---|")
    causes = Counter()
    for e in episodes:
        if e.get("outcome") == "success" and e.get("strategy") in FORM_CLOSURE:
            continue
        first = e.get("first_off_part")
        if "policy_note" in e:
            cause = "no plan"
            shown = f"no plan: {e['policy_note'].split(': ', 1)[-1]}"
        else:
            cause = ", ".join(first[0]) if first else "none"
            shown = f"{cause} ({first[1]})" if first else "none"
        if e.get("outcome") != "success":
            causes[cause] += 1
        label = f"{e.get('strategy', '-')} ({e.get('friction_share', float('nan')):.2f})"
        print(f"| {e.get('config_id', '?')} | {e['env']} | {e.get('outcome', 'cut short')} | "
              f"{label} | {e.get('opening', float('nan')):.2f} | {shown} |")  # fmt: skip
    counted = ", ".join(f"{c} {n}" for c, n in causes.most_common()) or "no such episode"
    print(f"\nfirst contact off the part, episodes short of success: {counted}")


if __name__ == "__main__":
    main()
