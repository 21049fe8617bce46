"""The report `misses.py` writes of a cell's recorded episodes: its misses sorted by outcome,
whether they reached the mark and how they ended, their failure modes, the grasps let go, and
every episode's grade by hinge side (doors), base and part."""

from __future__ import annotations

from collections import Counter

import numpy as np

from realikea.markdown import table
from realikea.rewards.terms import StageParams
from realikea.tasks.outcome import OUTCOMES

OPEN_ABOVE = StageParams().open_above  # normalized aperture above this: the reward's open jaws


def grades_by(rows: list[dict], key: str) -> list[tuple[str, ...]]:
    """Table rows: each value of the episodes' `key` (base, part) with its fail / partial /
    success counts."""
    counts: dict[str, Counter] = {}
    for r in rows:
        counts.setdefault(r[key], Counter())[r["outcome"]] += 1
    return [(value, *(str(c[o]) for o in OUTCOMES)) for value, c in sorted(counts.items())]


def opened_by_side(rows: list[dict]) -> list[tuple[str, str, str]]:
    """Table rows: each part's successes of its episodes on left- and on right-hinged doors."""
    counts: dict[tuple[str, str], list[int]] = {}
    for r in rows:
        tally = counts.setdefault((r["part"], r["hinge"]), [0, 0])
        tally[0] += r["outcome"] == "success"
        tally[1] += 1

    def opened(part: str, side: str) -> str:
        won, ran = counts.get((part, side), (0, 0))
        return f"{won} / {ran}" if ran else "–"

    return [(p, opened(p, "left"), opened(p, "right")) for p in sorted({r["part"] for r in rows})]


def report(rows: list[dict], cell: dict, mark: float, unit: str, command: str) -> str:
    """The misses of the episodes `command` ran, by (outcome, reached the mark, termination)
    and by failure mode; how many episodes of each outcome let go of a grasp; then the grades
    of each hinge side and each part on each side (doors), each base and each part."""
    missed = [r for r in rows if r["outcome"] != "success"]
    lost = [r for r in missed if r["peak_opening"] >= mark]
    peaks = [r["peak_opening"] for r in rows if r["outcome"] == "success"]
    spread = f"median {np.median(peaks):.2f}, least {min(peaks):.2f} {unit}" if peaks else "none"
    sorted_misses = Counter(
        (r["outcome"], "yes" if r["peak_opening"] >= mark else "no", r["termination"])
        for r in missed
    )
    modes = Counter(r["failure_mode"] for r in missed)
    by_outcome = {o: [r for r in rows if r["outcome"] == o] for o in OUTCOMES}
    released = [(o, str(len(e)), str(sum(r["let_go"] for r in e))) for o, e in by_outcome.items()]
    sides = []
    if cell["kind"] == "door":
        sides = [*table(("hinge side", *OUTCOMES), "lrrr", grades_by(rows, "hinge")), ""]
        sides += [
            *table(("part", "left: opened", "right: opened"), "lrr", opened_by_side(rows)),
            "",
        ]
    lines = [
        f"# {cell['category']} {cell['kind']}, {cell['resistance']}: where the misses go wrong",
        "",
        f"`{command}`, run with `record=` by `python experiments/generalist/misses.py`"
        + (" (same grades as the committed cell)" if command == cell["command"] else "")
        + f". Success mark {mark:g} {unit}, graded on the opening at the episode's end.",
        "",
        f"{len(missed)} of {len(rows)} episodes missed; **{len(lost)} of them had reached the "
        "mark and ended below it** (peak openings "
        + (", ".join(f"{r['peak_opening']:.2f}" for r in lost) or "none")
        + f" {unit}). The successes' peak openings: {spread}.",
        "",
        *table(
            ("outcome", "reached the mark", "ended by", "episodes"),
            "lllr",
            [(*key, str(n)) for key, n in sorted(sorted_misses.items())],
        ),
        "",
        *table(
            ("failure mode (`realikea/tasks/failure_modes.py`)", "misses"),
            "lr",
            [(mode, str(n)) for mode, n in sorted(modes.items())],
        ),
        "",
        "Let go: the jaws opened (normalized aperture above "
        f"{OPEN_ABOVE:g}, the reward's open jaws) after the episode's first engaged grasp.",
        "",
        *table(("outcome", "episodes", "let go of a grasp"), "lrr", released),
        "",
        *sides,
        *table(("base", *OUTCOMES), "lrrr", grades_by(rows, "base")),
        "",
        *table(("part", *OUTCOMES), "lrrr", grades_by(rows, "part")),
        "",
    ]
    return "\n".join(lines)
