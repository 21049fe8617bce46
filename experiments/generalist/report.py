"""The generalist's tables from the grids `evaluate.py` wrote:
experiments/generalist/results/table.md, and their pooled rates in results/figures.json.

    python experiments/generalist/report.py

Success per kind x category x mode with Wilson 95 % intervals for each grid found, pooled per
kind and over every cell, then the named differences per cell and pooled with Newcombe's
interval. The grids: the appendix-reward generalists (coacd/, hull/ and their variants), and
the default `gated` recipe's (`train_gated.py`: default/s<seed>/ and hull_high/s<seed>/, the
latter also on its own hull geometry, hull_high/s<seed>_own/; seeds 0-2 superseded, the aims'
seeds from aims.py, and those of the superseded defaults of round 1 in default_group_ppo/ and
hull_high_group_ppo/ and of round 18 in default_student_96/); default_doors2/s<seed>/ and
default/s<seed>_2500/ against the default per seed on the door kind, default_follow/s<seed>/ on
all cells pooled (the comparisons named before those runs); the door specialists
(doors/s<seed>/) on the door cells.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from aims import SEEDS as AIM_SEEDS
from cell_tables import difference_markdown, success_table

from realikea.eval.library_grid import KINDS, pooled, read_cells
from realikea.eval.stats import describe, diff_interval, significant, wilson
from realikea.files import atomic_write_text
from realikea.reports.multiplicity import Difference, holm_lines
from realikea.sim.resistance import MODES

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
SUPERSEDED_SEEDS = (0, 1, 2)  # the single-task generalists (train_gated.py)
ITERATIONS = "1,500 iterations"
STAGED = "teachers then a student of 400 iterations"
STAGED_MORE = "teachers then a student of 400 iterations and 200 more"  # round 27's student_more

# the `gated` recipes' runs, (folder, what was trained, seeds, length): the superseded
# single-task generalists (seeds 0-2), the superseded defaults' runs of the aims' seeds (round 1's
# group_ppo, round 18's pipeline) and the aims' (aims.py: python train.py's defaults, since round
# 19's adoption its pipeline)
GATED = (
    ("default", "the superseded default (`python train.py pipeline=none agent=ppo`: CoACD, "
     "normal, `gated`, the single-task agent)", SUPERSEDED_SEEDS, ITERATIONS),
    ("hull_high", "the design card's `python train.py collision=hull resistance=high` on the "
     "superseded single-task agent", SUPERSEDED_SEEDS, ITERATIONS),
    ("default_doors2", "the superseded default with door groups drawn twice as often "
     "(`asset.group_weights={door:2}`)", SUPERSEDED_SEEDS, ITERATIONS),
    ("default_follow", "the superseded default with a draw that follows training success "
     "(`asset.follow_success={every:50,below:0.5,weight:3}`)", SUPERSEDED_SEEDS, ITERATIONS),
    ("default_group_ppo", "the superseded default of round 1 (`python train.py pipeline=none`: "
     "CoACD, normal, `gated`, `agent=multitask`)", AIM_SEEDS["default"], ITERATIONS),
    ("hull_high_group_ppo", "the design card's `python train.py collision=hull resistance=high` "
     "on the superseded default of round 1 (`pipeline=none`, `agent=multitask`)",
     AIM_SEEDS["hull_high"], ITERATIONS),
    ("default_student_96", "the superseded default of round 18 (`python train.py "
     "pipeline=distilled_pairs_student_96`: CoACD, normal, `gated`)", AIM_SEEDS["default"][:2],
     STAGED),
    ("default_fine_tune", "the superseded default of round 19 (`python train.py "
     "pipeline=distilled_pairs_fine_tune`: CoACD, normal, `gated`)", AIM_SEEDS["default"][:2],
     STAGED),
    ("default_validated_marks", "the superseded default of round 21 (`python train.py "
     "pipeline=distilled_pairs_validated_marks`: CoACD, normal, `gated`)", AIM_SEEDS["default"],
     STAGED),
    ("default_student_mean", "the superseded default of round 23 (`python train.py "
     "pipeline=distilled_pairs_student_mean`: CoACD, normal, `gated`)", AIM_SEEDS["default"][:2],
     STAGED),
    ("default_student_noise", "the superseded default of round 24 (`python train.py "
     "pipeline=distilled_pairs_student_noise`: CoACD, normal, `gated`)", AIM_SEEDS["default"],
     STAGED),
    ("default_judged_high", "the superseded default of round 25 (`python train.py "
     "pipeline=distilled_pairs_judged_high`: CoACD, normal, `gated`)", AIM_SEEDS["default"],
     STAGED),
    ("hull_high_judged_high", "the design card's `python train.py collision=hull "
     "resistance=high` on the superseded default of round 25 "
     "(`pipeline=distilled_pairs_judged_high`)", AIM_SEEDS["hull_high"][:1], STAGED),
    ("default_small_parts", "the superseded default of round 26 (`python train.py "
     "pipeline=distilled_pairs_small_parts`: CoACD, normal, `gated`)", AIM_SEEDS["default"],
     STAGED),
    ("hull_high_small_parts", "the design card's `python train.py collision=hull "
     "resistance=high` on the superseded default of round 26 "
     "(`pipeline=distilled_pairs_small_parts`)", AIM_SEEDS["hull_high"][:1], STAGED),
    ("default_student_small_parts", "the superseded default of round 27 (`python train.py "
     "pipeline=distilled_pairs_student_small_parts`: CoACD, normal, `gated`)",
     AIM_SEEDS["default"], STAGED_MORE),
    ("hull_high_student_small_parts", "the design card's `python train.py collision=hull "
     "resistance=high` on the superseded default of round 27 "
     "(`pipeline=distilled_pairs_student_small_parts`)", AIM_SEEDS["hull_high"][:2], STAGED_MORE),
    ("default", "the adopted default (`python train.py`: CoACD, normal, `gated`, "
     "`pipeline=distilled_pairs_student_mirrored`)", AIM_SEEDS["default"], STAGED_MORE),
    ("hull_high", "the design card's `python train.py collision=hull resistance=high` "
     "(`pipeline=distilled_pairs_student_mirrored`)", AIM_SEEDS["hull_high"], STAGED_MORE),
)  # fmt: skip

GRIDS = {  # folder -> what was trained
    "coacd": "CoACD, w_open2 = 2, 1,500 iterations",
    "hull": "hull, w_open2 = 2, 1,500 iterations",
    "coacd_2500": "CoACD, w_open2 = 2, continued to 2,500 iterations",
    "coacd_open2_0": "CoACD, w_open2 = 0, 1,500 iterations",
    "hull_open2_0": "hull, w_open2 = 0, 1,500 iterations",
    **{
        f"{recipe}/s{seed}{own}": f"{what}, seed {seed}, {length}"
        for recipe, what, seeds, length in GATED
        for seed in seeds
        for own in (("", "_own") if recipe.startswith("hull_high") else ("",))
    },
    **{
        f"default/s{seed}_2500": f"the superseded default, seed {seed}, continued to 2,500 "
        "iterations"
        for seed in (0, 2)
    },
    **{
        f"doors/s{seed}": f"a door specialist (`asset.kind=door`), seed {seed}, 600 iterations"
        for seed in (0, 1, 2, 3)
    },
}
COMPARISONS = (  # (grid a, grid b, title, the two columns' names)
    ("coacd", "hull", "CoACD vs hull, w_open2 = 2", ("CoACD", "hull")),
    ("coacd_open2_0", "hull_open2_0", "CoACD vs hull, w_open2 = 0", ("CoACD", "hull")),
    ("hull_open2_0", "coacd", "each source with its better bonus", ("hull 0", "CoACD 2")),
    ("coacd_2500", "coacd", "2,500 vs 1,500 iterations (CoACD)", ("2,500 its", "1,500 its")),
    # named before the gated runs finished: what the reward changed, seed 0 of each
    ("default/s0", "coacd", "the gated default vs the appendix generalist (CoACD, normal)",
     ("gated", "appendix")),
    ("hull_high/s0_own", "hull_high/s0", "the design card's policy on its hull vs on CoACD",
     ("own hull", "CoACD")),
)  # fmt: skip


# per-kind comparisons named before their runs (README): (title, a, b, the seeds, a's name, the
# named rows: a kind, or "all" for every cell pooled); per seed each kind and all cells, in
# smooth and in high, a against b, Holm over the named rows of the seeds and modes
KIND_FAMILIES = (
    ("Doors drawn twice as often vs the default", "default_doors2/s{}", "default/s{}", (0, 1),
     "doors2", "door"),
    ("2,500 vs 1,500 iterations of the default", "default/s{}_2500", "default/s{}", (0, 2),
     "2,500 its", "door"),
    ("A draw that follows training success vs the default", "default_follow/s{}", "default/s{}",
     (0, 1), "follow", "all"),
)  # fmt: skip


def kind_family_lines(
    grids: dict, title: str, a: str, b: str, seeds, name: str, named: str
) -> list[str]:
    """Each kind and all cells pooled per seed and mode, a minus b, with Newcombe's interval,
    then Holm's verdict over the `named` rows (the others reported)."""
    lines = [f"## {title}, per seed (named before the runs)", ""]
    lines += [
        f"| seed | mode | kind | {name} | default | {name} − default [95 %] |",
        "|---|---|---|---|---|---|",
    ]
    family = []
    for seed in seeds:
        ga, gb = grids.get(a.format(seed)), grids.get(b.format(seed))
        if ga is None or gb is None:
            continue
        for mode in ("smooth", "high"):
            for kind in (*KINDS, "all"):
                pick = None if kind == "all" else kind
                (k1, n1), (k2, n2) = pooled(ga, mode, pick), pooled(gb, mode, pick)
                if not (n1 and n2):  # a grid still being evaluated
                    continue
                d = Difference(f"seed {seed}, {mode}, {kind}", [(k1, n1)], [(k2, n2)])
                diff, lo, hi = d.interval()
                lines.append(
                    f"| {seed} | {mode} | {kind} | {describe(k1, n1)} | {describe(k2, n2)} | "
                    f"{diff:+.2f} [{lo:+.2f}, {hi:+.2f}] |"
                )
                if kind == named:
                    family.append(d)
    if not family:
        return []
    rows = "all cells" if named == "all" else f"{named}s"
    heading = f"The named family: {rows}, per seed and mode (Holm)"
    return [*lines, "", *holm_lines(family, heading, "###"), ""]


def comparison_lines(a: dict, b: dict, title: str, names: tuple[str, str]) -> list[str]:
    """Per-cell and pooled differences of two grids (a − b) with Newcombe's interval."""
    lines = [f"## {title}", "", difference_markdown(a, b, names), ""]
    for mode in MODES:
        (k1, n1), (k2, n2) = pooled(a, mode), pooled(b, mode)
        if n1 and n2:
            lo, hi = diff_interval(k1, n1, k2, n2)
            verdict = "significant" if significant(k1, n1, k2, n2) else "not significant"
            lines.append(
                f"- all cells, {mode}: {k1 / n1:.2f} vs {k2 / n2:.2f}, "
                f"{k1 / n1 - k2 / n2:+.2f} [{lo:+.2f}, {hi:+.2f}] ({verdict})"
            )
    return [*lines, ""]


def figures(grids: dict[str, dict]) -> dict:
    """Per grid and mode, every cell pooled and each kind pooled: successes, episodes and the
    rate with its Wilson interval (what the READMEs quote by key)."""

    def rate(k: int, n: int) -> dict:
        return {"successes": k, "episodes": n, "rate": [k / n, *wilson(k, n)]}

    out: dict = {}
    for name, cells in grids.items():
        for mode in MODES:
            k, n = pooled(cells, mode)
            if n:
                kinds = {kind: pooled(cells, mode, kind) for kind in KINDS}
                out.setdefault(name, {})[mode] = {
                    "all": rate(k, n),
                    **{kind: rate(*kn) for kind, kn in kinds.items() if kn[1]},
                }
    return out


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    grids = {name: read_cells(RESULTS / name / "cells.jsonl") for name in GRIDS}
    grids = {name: cells for name, cells in grids.items() if cells}
    lines = ["# The generalist on the held-out parts", ""]
    for name, cells in grids.items():
        first = next(iter(cells.values()))
        lines += [
            f"## Trained with {GRIDS[name]}, evaluated with `{first['collision']}` collision, "
            f"scene {first['scene']}, split {first['split']}, env.seed={first['seed']}, "
            f"{first['episodes']} episodes a cell, randomized poses",
            "",
            success_table(cells),
        ]
        for mode in MODES:
            k, n = pooled(cells, mode)
            if n:
                per_kind = {kind: pooled(cells, mode, kind) for kind in KINDS}
                kinds = ", ".join(
                    f"{kind} {describe(*kn)}" for kind, kn in per_kind.items() if kn[1]
                )
                lines.append(f"- all cells, {mode}: {describe(k, n)}; per kind: {kinds}")
        lines.append("")
    for a, b, title, names in COMPARISONS:
        if a in grids and b in grids:
            lines += comparison_lines(grids[a], grids[b], title, names)
    for family in KIND_FAMILIES:
        lines += kind_family_lines(grids, *family)
    atomic_write_text(RESULTS / "table.md", "\n".join(lines))
    atomic_write_text(RESULTS / "figures.json", json.dumps(figures(grids), indent=1) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
