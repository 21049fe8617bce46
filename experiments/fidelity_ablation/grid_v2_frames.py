"""Which of the grid v2 runs' frame strips its report shows, chosen by a fixed rule, never by eye.

A strip (grid_v2_eval.py) is four frames of the first recorded episode that succeeded with a
strategy label, under the run's training resistance. The report shows a hook and a pinch per
source on two-point x high (the lowest seed that recorded each) and three successes per label the
registered comparisons count, from three different cells (the first in the cell table's order).
"""

from __future__ import annotations

from pathlib import Path

from grid_v2 import CATEGORIES, COLLISIONS, RESISTANCES
from grid_v2_eval import VIDEO_EPISODES

LABELS = ("hook", "lever", "pinch")  # the labels the registered comparisons count
PER_LABEL = 3


def success_strip(run: dict, label: str) -> Path | None:
    path = run["dir"] / "videos" / f"eval_{label}_success.png"
    return path if path.is_file() else None


def cell(run: dict) -> tuple[str, str, str]:
    return run["category"], run["resistance"], run["collision"]


def cell_order(run: dict) -> tuple[int, int, int, int]:
    """The cell table's order: category, training resistance, source, then seed."""
    category, resistance, collision = cell(run)
    return (
        CATEGORIES.index(category),
        RESISTANCES.index(resistance),
        COLLISIONS.index(collision),
        run["seed"],
    )


def two_point_high(runs: list[dict]) -> list[tuple[str, str, dict | None]]:
    """(source, label, the lowest-seed two-point x high run of that source with such a strip)."""
    found = []
    for collision in COLLISIONS:
        ordered = sorted(
            (r for r in runs if cell(r) == ("two_point", "high", collision)), key=cell_order
        )
        for label in ("hook", "pinch"):
            found.append(
                (collision, label, next((r for r in ordered if success_strip(r, label)), None))
            )
    return found


def per_label(runs: list[dict], label: str) -> list[dict]:
    """The first PER_LABEL runs with a success strip of `label`, at most one per cell."""
    chosen: list[dict] = []
    for run in sorted(runs, key=cell_order):
        if success_strip(run, label) and cell(run) not in {cell(c) for c in chosen}:
            chosen.append(run)
    return chosen[:PER_LABEL]


def frame_lines(runs: list[dict]) -> list[str]:
    """The report's frames section; image paths are relative to the kept runs' folder."""

    def image(run: dict, label: str) -> list[str]:
        name = run["name"]
        return [
            f"`{name}`, `{label}`:",
            "",
            f"![{name} {label}]({name}/videos/eval_{label}_success.png)",
            "",
        ]

    lines = [
        "## Frames",
        "",
        f"Four frames of the first recorded episode (of {VIDEO_EPISODES}, under the run's "
        "training resistance, "
        "`grid_v2_eval.py`) that succeeded with the label, the scene above a close-up of the "
        "handle; chosen by the rule in `grid_v2_frames.py`, not by eye.",
        "",
        "### Two-point x high: a hook and a pinch per source (lowest seed that recorded one)",
        "",
    ]
    for collision, label, run in two_point_high(runs):
        lines += image(run, label) if run else [f"{collision}, `{label}`: no recorded success.", ""]
    for label in LABELS:
        chosen = per_label(runs, label)
        lines += [f"### `{label}`: {len(chosen)} successes from different cells", ""]
        for run in chosen:
            lines += image(run, label)
    return lines
