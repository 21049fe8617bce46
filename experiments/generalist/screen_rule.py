"""The generalist screen's adoption rule, applied to a candidate's runs (written before them):
adopt a candidate only if, on every seed run, every category x kind group's training success over
the run's last full 25-iteration window is at least the round's mark (MARKS: LEARNED in round 1,
0.8 from round 2 on, README.md).

    python experiments/generalist/screen_rule.py RUN_DIR [RUN_DIR ...]              # round 1
    python experiments/generalist/screen_rule.py --mark 0.8 RUN_DIR [RUN_DIR ...]   # rounds 2-6
    python experiments/generalist/screen_rule.py --mark 0.8 --pad-enters RUN_DIR ... # rounds 7 on

A run's last full window is its last 25 iterations (iterations N - 25 .. N - 1 of a run that
logged N); a group's value is the mean of its `/success/<category>_<kind>` entries there (an
entry is that iteration's share of the group's finished episodes). A group with no entry in the
window, or a run shorter than the window, fails (`realikea.training.metrics.last_window`). With
`--pad-enters` (rounds 7 on) a finger-pull group is read on the episodes whose part's channel
the pad enters (`/pad_enters_success/finger_pull_<kind>`). Prints a row per run and the verdict;
exit 0 when the candidate is adopted, 1 when not, 2 on bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from screen_candidates import ROUNDS

from realikea.assets.catalog import GROUPS
from realikea.training.metrics import last_window

LEARNED = 0.5
# each registered screen round's mark: every group's least training success
MARKS = {round_: LEARNED if round_ == 1 else 0.8 for round_ in ROUNDS}
PAD_ENTERS_ROUNDS = {r for r in ROUNDS if r >= 7}  # finger pulls read on channels the pad enters


def passes(values: dict[str, float | None], mark: float = LEARNED) -> bool:
    return all(v is not None and v >= mark for v in values.values())


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", type=Path, metavar="RUN_DIR", help="one per seed")
    parser.add_argument("--mark", type=float, default=LEARNED, help="a group's least success")
    parser.add_argument(
        "--pad-enters", action="store_true", help="finger pulls on channels the pad enters"
    )
    args = parser.parse_args(argv)
    runs = args.runs
    if not 0.0 < args.mark <= 1.0:
        print(f"screen_rule.py: --mark {args.mark} is not a rate in (0, 1]", file=sys.stderr)
        return 2
    missing = [r for r in runs if not (r / "metrics.csv").is_file()]
    if missing:
        print(f"screen_rule.py: no metrics.csv in {', '.join(map(str, missing))}", file=sys.stderr)
        return 2
    print("| run | " + " | ".join(GROUPS) + " | passes |")
    print("|---|" + "---:|" * len(GROUPS) + "---|")
    verdicts = []
    for run in runs:
        values = last_window(run, args.pad_enters)
        verdicts.append(passes(values, args.mark))
        shown = ["–" if v is None else f"{v:.2f}" for v in values.values()]
        print(f"| {run} | " + " | ".join(shown) + f" | {'yes' if verdicts[-1] else 'no'} |")
    adopted = all(verdicts)
    print(
        f"adopted: {'yes' if adopted else 'no'} "
        f"({sum(verdicts)} of {len(runs)} runs pass at {args.mark:g})"
    )
    return 0 if adopted else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
