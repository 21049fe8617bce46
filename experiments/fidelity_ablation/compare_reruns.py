"""Whether two re-evaluations of the committed runs agree: every run's eval.json under OLD and NEW
compared mode by mode (outcomes, strategy fractions, contact statistics, mean return).

    python experiments/fidelity_ablation/compare_reruns.py OLD_RUNS_DIR NEW_RUNS_DIR

OLD is typically a worktree of an earlier commit after `realikea eval rerun` there. Prints one
row per run: identical, or the largest absolute difference and where.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

COMPARED = ("fail", "partial", "success", "strategies", "success_strategies", "contacts",
            "mean_return", "pulled_episodes")  # fmt: skip


def flat(value, prefix: str = "") -> dict[str, float]:
    if isinstance(value, dict):
        return {k: v for key, sub in value.items() for k, v in flat(sub, f"{prefix}{key}.").items()}
    return {prefix.rstrip("."): value}


def compare(old: dict, new: dict) -> tuple[float, str]:
    """The largest absolute difference between the compared figures, and its key."""
    worst, where = 0.0, ""
    for mode, figures in old["modes"].items():
        a = flat({k: figures.get(k) for k in COMPARED})
        b = flat({k: new["modes"].get(mode, {}).get(k) for k in COMPARED})
        for key in a.keys() | b.keys():
            x, y = a.get(key), b.get(key)
            diff = (
                abs(x - y)
                if isinstance(x, int | float) and isinstance(y, int | float)
                else (0.0 if x == y else float("inf"))
            )
            if diff > worst:
                worst, where = diff, f"{mode}.{key}"
    return worst, where


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old_dir", type=Path, metavar="OLD_RUNS_DIR")
    parser.add_argument("new_dir", type=Path, metavar="NEW_RUNS_DIR")
    args = parser.parse_args(argv)
    old_dir, new_dir = args.old_dir, args.new_dir
    old_files = sorted(old_dir.glob("*/eval.json"))
    if not old_files:
        print(f"compare_reruns.py: no <run>/eval.json under {old_dir}", file=sys.stderr)
        return 2
    print("| run | old vs new |\n|---|---|")
    same = True
    for old_file in old_files:
        new_file = new_dir / old_file.parent.name / "eval.json"
        if not new_file.is_file():
            same = False
            print(f"| {old_file.parent.name} | missing: {new_file} |")
            continue
        worst, where = compare(json.loads(old_file.read_text()), json.loads(new_file.read_text()))
        same &= worst == 0.0
        verdict = "identical" if worst == 0.0 else f"max |diff| {worst:.3g} at {where}"
        print(f"| {old_file.parent.name} | {verdict} |")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
