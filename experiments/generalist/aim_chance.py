"""How likely an aim's verdict is to repeat on a fresh draw of episodes (describing; it chooses
nothing): the chance that a policy meets the aims (`aims_report.py`'s marks, a point estimate
per cell from n episodes) if its true rate were the same p in every counted cell, and, per kept
aim run, the chance that a fresh read of every cell clears its mark, given the cell's own read:
results/aim_chance.md.

    python experiments/generalist/aim_chance.py
    python experiments/generalist/aim_chance.py --episodes 100   # the same with n episodes
    python experiments/generalist/aim_chance.py --superseded student_small_parts   # round 27's

`--superseded NAME` reads the aim runs of a recipe the defaults no longer train, kept in
`<recipe>_NAME/` (as `aims_report.py --superseded NAME`), into aim_chance_NAME.md.

Each cell's fresh read is drawn from the Jeffreys posterior of its rate (Beta(k + 1/2,
n - k + 1/2)), so its chance is a beta-binomial tail. Cells are taken as independent; the
smooth and high reads of one group share a policy, so the products are rough where both are
near their marks.
"""

from __future__ import annotations

import argparse
import math

from aims import GROUPS, RESULTS, SEEDS
from aims_report import MARKS, excluded, hull_fp_door_opened, recipe_folders
from scipy.stats import betabinom, binom

from realikea.eval.library_grid import cell_count, read_cells
from realikea.files import atomic_write_text
from realikea.markdown import table

EPISODES = 50  # the aims' episodes a cell
SAME_RATES = (0.75, 0.8, 0.85, 0.9, 0.95)


def needed(mark: float, n: int) -> int:
    """The fewest successes of n whose rate is at or above the mark."""
    return math.ceil(mark * n - 1e-9)


def aims() -> list[tuple[str, str, dict[str, float], set]]:
    """Each judged evaluation: (recipe, suffix, its marks by mode, the groups it leaves out)."""
    opened = hull_fp_door_opened()
    return [
        (recipe, suffix, marks, excluded(recipe, suffix, opened))
        for (recipe, suffix), marks in MARKS.items()
        if marks
    ]


def same_rate_chance(p: float, marks: dict[str, float], counted: int, n: int) -> float:
    """The chance that `counted` groups, each at true rate p, clear every mode's mark."""
    return math.prod(binom.sf(needed(m, n) - 1, n, p) ** counted for m in marks.values())


def fresh_read_chance(k: int, n_read: int, mark: float, n: int) -> float:
    """The chance that a fresh n-episode read clears the mark, given k of n_read (Jeffreys)."""
    return float(betabinom.sf(needed(mark, n) - 1, n, k + 0.5, n_read - k + 0.5))


def seed_rows(
    recipe: str, folder: str, suffix: str, marks: dict, skip: set, n: int
) -> list[list[str]]:
    """Per seed of the recipe's aim runs kept in `folder`: its verdict's chance to repeat and its
    three least likely cells."""
    rows = []
    for seed in SEEDS[recipe]:
        path = RESULTS / folder / f"s{seed}{suffix}" / "cells.jsonl"
        if not path.is_file():
            rows.append([f"s{seed}", "not evaluated", "–", "–"])
            continue
        cells, chances, below = read_cells(path), [], False
        counted = [(kd, cat, md) for kd, cat in GROUPS if (kd, cat) not in skip for md in marks]
        if any(cell not in cells for cell in counted):
            rows.append([f"s{seed}", "not all cells evaluated", "–", "–"])
            continue
        for kind, category, mode in counted:
            k, n_read = cell_count(cells[(kind, category, mode)])
            below |= k < needed(marks[mode], n_read)
            chance = fresh_read_chance(k, n_read, marks[mode], n)
            name = f"{category.replace('_', '-')} {kind}s {mode}"
            chances.append((chance, f"{name} {k}/{n_read}: {chance:.2f}"))
        read = "missed" if below else "met"
        weakest = "; ".join(text for _, text in sorted(chances)[:3])
        rows.append([f"s{seed}", read, f"{math.prod(c for c, _ in chances):.2f}", weakest])
    return rows


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=EPISODES, help="episodes a fresh read")
    parser.add_argument(
        "--superseded", metavar="NAME", default="", help="a superseded recipe: <recipe>_NAME/"
    )
    args = parser.parse_args(argv)
    n, superseded = args.episodes, args.superseded
    if n < 1:
        parser.error(f"--episodes {n}: need at least 1")
    folders = recipe_folders(parser, superseded, RESULTS)
    title = f": `{superseded}`, superseded" if superseded else ""
    command = " ".join(["--episodes", str(n), *(["--superseded", superseded] * bool(superseded))])
    lines = [
        f"# How likely the aims' verdicts are to repeat{title}",
        "",
        f"`python experiments/generalist/aim_chance.py {command}`: the aims' marks "
        f"(`aims_report.py`) held to a fresh read of {n} episodes a cell. Describing; cells "
        "taken as independent.",
        "",
        "## A policy at the same true rate in every counted cell",
        "",
    ]
    judged = aims()  # reads the hull finger-pull door check once
    header = ["aim", "cells", *(f"p = {p:.2f}" for p in SAME_RATES)]
    rows = []
    for recipe, suffix, marks, skip in judged:
        counted = len(GROUPS) - len(skip)
        name = f"`{recipe}`{' own hull' if suffix else ''}: " + ", ".join(
            f"≥ {m:g} {mode}" for mode, m in marks.items()
        )
        chances = [same_rate_chance(p, marks, counted, n) for p in SAME_RATES]
        rows.append([name, str(counted * len(marks)), *(f"{c:.2f}" for c in chances)])
    lines += [*table(header, "lr" + "r" * len(SAME_RATES), rows), ""]
    for recipe, suffix, marks, skip in judged:
        where = " on its own hull" if suffix else ""
        lines += [
            f"## `{folders[recipe]}`{where}: each kept seed's verdict on a fresh read",
            "",
            "The chance that a fresh read of every counted cell clears its mark, given each "
            "cell's own read (Jeffreys posterior), and its three least likely cells.",
            "",
            *table(
                ["seed", "read", "chance to meet", "least likely cells"],
                "llrl",
                seed_rows(recipe, folders[recipe], suffix, marks, skip, n),
            ),
            "",
        ]
    name = "aim_chance" + f"_{superseded}" * bool(superseded)
    name += f"_{n}.md" if n != EPISODES else ".md"
    atomic_write_text(RESULTS / name, "\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
