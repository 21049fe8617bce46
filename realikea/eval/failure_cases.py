"""Scripted episodes built to fail in each of the paper's four modes, and how often the failure
classifier (realikea/tasks/failure_modes.py) names the mode each was built for.

    realikea eval failures [--episodes 20] [--seed 1000] [--out FILE.md]

Each case is a policy and a scene chosen so that it fails one way, on the held-out drawers of
its category in the kitchen (randomized poses, the draw of `env.seed`); its agreement is the
share of its failed episodes given that mode.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from realikea.assets.catalog import Catalog
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.stats import wilson
from realikea.files import atomic_write_text
from realikea.markdown import table
from realikea.policies.scripted import CLOSE, OPEN, Waypoint, WaypointPolicy
from realikea.tasks.facts import SceneFacts
from realikea.tasks.failure_modes import FAILURE_MODES

AGREEMENT = 0.9  # the classifier's required agreement with these cases' built-in outcome


class PressBeside(WaypointPolicy):
    """Drives the closed hand into the neighbouring front beside a drawer's own, at the handle's
    height, and pulls there: the scene, not the part, stops the hand."""

    name = "press_beside"
    BEYOND = 0.08  # m past the front's side edge
    PRESS = 0.03  # m into the neighbour's face

    def plan(self, facts: SceneFacts) -> list[Waypoint]:
        base = Catalog.load().base(facts.config_id.partition("__")[2])
        side, normal = facts.part_rot[:, 0], facts.part_rot[:, 2]
        beside = facts.handle_pos + (base.width * (1 - base.mount_u) + self.BEYOND) * side
        return [
            Waypoint(beside + 0.08 * normal, 0.0, OPEN, tolerance=0.01),
            Waypoint(beside + 0.08 * normal, 0.0, CLOSE, tolerance=1.0, hold=5, timeout=6),
            Waypoint(beside - self.PRESS * normal, 0.0, CLOSE, tolerance=0.0, timeout=40),
            Waypoint(beside + 0.3 * facts.pull_dir, 0.0, CLOSE, tolerance=0.0, timeout=10**9),
        ]


@dataclass(frozen=True)
class FailureCase:
    """A policy on a scene that fails in `mode`, and why it does."""

    mode: str
    overrides: tuple[str, ...]
    why: str
    policy: type[WaypointPolicy] | None = None  # else the overrides' policy


CASES = (
    FailureCase(
        "slip",
        ("policy=heuristic_pull", "asset=knob", "gripper.grasp_force=5", "resistance=high"),
        "a 5 N pinch on a knob against the 20 N breakaway of a drawer in high",
    ),
    FailureCase(
        "mutual_interference",
        (
            "policy=heuristic_pull",
            "asset=two_point",
            "asset.base=drawer_w40_h20",
            "resistance=high",
        ),
        "the closed hand pressed into the neighbouring front beside a 40 cm drawer (within reach)",
        PressBeside,
    ),
    FailureCase(
        "narrow_clearance",
        ("policy=hook_oracle", "asset=two_point", "collision=hull", "gripper=menagerie_servo"),
        "the hook oracle's fingertips against a two-point bar's sealed hull, with Menagerie's "
        "servo hand (its squeeze under 1 N: no pinch to fall back on)",
    ),
    FailureCase(
        "specialized_design",
        ("policy=hook_oracle", "asset=finger_pull", "policy.lip_pitch=0.0", "resistance=high"),
        "the hook oracle under a finger pull's lip with the wrist never tipped up",
    ),
)


def run_case(case: FailureCase, episodes: int, seed: int) -> Counter:
    """Failure modes of the case's failed episodes (successes counted as `success`)."""
    overrides = [*case.overrides, "asset.kind=drawer", "dr=randomized", f"env.seed={seed}"]
    cfg, policy = eval_setup([*overrides, f"episodes={episodes}"])
    if case.policy is not None:
        policy = case.policy.from_config(cfg)
    result = evaluate(cfg, policy)
    return Counter(e.get("failure_mode") or "success" for e in result.episodes)


def report(counts: dict[FailureCase, Counter]) -> str:
    """A markdown table of each case's modes and its agreement with Wilson's 95 % interval."""
    header = ["built to fail by", "case", "failed", *FAILURE_MODES, "agreement [95 %]"]
    rows = []
    for case, c in counts.items():
        failed = sum(v for k, v in c.items() if k != "success")
        hit = c[case.mode]
        lo, hi = wilson(hit, failed) if failed else (np.nan, np.nan)
        share = f"{hit / failed:.2f} [{lo:.2f}, {hi:.2f}]" if failed else "no failure"
        rows.append([case.mode, case.why, str(failed), *(str(c[m]) for m in FAILURE_MODES), share])
    return "\n".join(table(header, "llr" + "r" * len(FAILURE_MODES) + "l", rows))


def validate(episodes: int, seed: int, out: Path | None) -> int:
    """Run every case; print (and write to `out`) the table; 1 if a case misses the bar."""
    counts = {case: run_case(case, episodes, seed) for case in CASES}
    table = report(counts)
    print(table)
    if out is not None:
        command = f"realikea eval failures --episodes {episodes} --seed {seed}"
        body = f"# Failure modes on episodes built to fail\n\n`{command}`\n\n{table}\n"
        atomic_write_text(Path(out), body)
    missed = [
        case.mode
        for case, c in counts.items()
        if c[case.mode] < AGREEMENT * max(sum(v for k, v in c.items() if k != "success"), 1)
    ]
    for mode in missed:
        print(f"agreement below {AGREEMENT:.0%}: {mode}")
    return 1 if missed else 0
