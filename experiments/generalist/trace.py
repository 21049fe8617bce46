"""One episode of a policy, step by step: the front's opening, the reward's stage, the fingers
touching the part and whether one hooks it (as the stage read them), the jaws' aperture and the
policy's gripper command after each control step.

    python experiments/generalist/trace.py --episode 7 [--out FILE.md] EVAL_OVERRIDES...

EVAL_OVERRIDES are `realikea eval`'s (e.g. policy=checkpoint policy.path=... asset=finger_pull
asset.kind=door resistance=smooth dr=randomized asset.split=train env.seed=2000). The episode is
the one `realikea eval ... video=true` shows at that index: the draw's configuration number
`--episode` (from 0), seeded env.seed plus it (`realikea.eval.video.drawn_tasks`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from realikea.eval.record import ACTION_NAMES
from realikea.eval.setup import eval_setup
from realikea.eval.video import drawn_tasks
from realikea.files import atomic_write_text, shown_path
from realikea.markdown import table
from realikea.policies.rollout import episode

GRIPPER = ACTION_NAMES.index("gripper")


def touching(grip) -> str:
    """The fingers on the part: left, right, both or neither (–)."""
    return " ".join(side for side, on in (("left", grip.left), ("right", grip.right)) if on) or "–"


def trace(task, policy) -> tuple[list[tuple], dict]:
    """Run one episode; each step's (step, opening, stage, fingers on the part, hooked,
    aperture, gripper command) and the episode's final info."""
    commands = []

    def keep_command(t: int, action: np.ndarray) -> np.ndarray:
        commands.append(float(action[GRIPPER]))
        return action

    steps, info = [], {}
    for result in episode(task, policy, keep_command):
        grip, info = task.grip, result.info  # as this step's stage read it; the last: the episode's
        steps.append(
            (len(steps), task.opening, task.state.stage, touching(grip), grip.hooked,
             task.aperture, commands[-1])
        )  # fmt: skip
    return steps, info


def report(steps: list[tuple], info: dict, name: str, command: str) -> str:
    """The trace as markdown: what ran, how it ended, then one row per step."""
    rows = [
        (str(k), f"{opening:.2f}", str(stage), on, "yes" if hooked else "no", f"{aperture:.2f}",
         f"{grip:+.2f}")
        for k, opening, stage, on, hooked, aperture, grip in steps
    ]  # fmt: skip
    return "\n".join(
        [
            f"# {name}: one episode, step by step",
            "",
            f"`python experiments/generalist/trace.py {command}`",
            "",
            f"Ended: {info['outcome']} ({info['termination']}), opening {info['opening']:.2f}, "
            f"failure mode {info.get('failure_mode') or 'none'}. The gripper command is the "
            "policy's (negative closes the jaws); aperture 0 is closed, 1 open.",
            "",
            *table(
                (
                    "step",
                    "opening",
                    "stage",
                    "fingers on the part",
                    "hooked",
                    "aperture",
                    "gripper command",
                ),
                "rrrllrr",
                rows,
            ),
            "",
        ]
    )


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episode", type=int, required=True, help="the draw's index, from 0")
    parser.add_argument("--out", type=Path, help="also write the trace to this markdown file")
    parser.add_argument("overrides", nargs="+", help="realikea eval's Hydra overrides")
    args = parser.parse_args(argv)
    if args.episode < 0:
        parser.error(f"--episode {args.episode}: use 0 or more")
    cfg, policy = eval_setup(args.overrides)
    task = drawn_tasks(cfg, args.episode + 1)[args.episode]
    steps, info = trace(task, policy)
    command = " ".join([f"--episode {args.episode}", *args.overrides])
    text = report(steps, info, task.config_id, command)
    print(text)
    if args.out:
        atomic_write_text(args.out, text)
        print(f"written: {shown_path(args.out)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
