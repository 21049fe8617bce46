"""Holm's correction over a report's family of differences: which stay significant when every
difference the report tests counts, not only the one quoted."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from realikea.eval.stats import diff_interval, diff_p, holm, seed_difference, seed_difference_p

Runs = Sequence[tuple[int, int]]  # (count, episodes) per training seed


@dataclass(frozen=True)
class Difference:
    """One tested difference of two groups' rates (a minus b) and what names it."""

    label: str
    a: Runs
    b: Runs

    def interval(self) -> tuple[float, float, float]:
        """(difference, low, high): Newcombe's with one run a side, else the seed bootstrap."""
        if len(self.a) == 1 and len(self.b) == 1:
            (k1, n1), (k2, n2) = self.a[0], self.b[0]
            return (k1 / n1 - k2 / n2, *diff_interval(k1, n1, k2, n2))
        return seed_difference(self.a, self.b)

    def p(self) -> float:
        """The two-sided p-value that agrees with `interval`."""
        if len(self.a) == 1 and len(self.b) == 1:
            (k1, n1), (k2, n2) = self.a[0], self.b[0]
            return diff_p(k1, n1, k2, n2)
        return seed_difference_p(self.a, self.b)


def holm_lines(family: Sequence[Difference], title: str, heading: str = "##") -> list[str]:
    """A Markdown section (`heading` title): the family's size, how many differences exclude
    zero before and after Holm's correction, and a row for each that does before it."""
    ps = [d.p() for d in family]
    adjusted = holm(ps)
    uncorrected = [i for i in np.argsort(ps, kind="stable") if ps[i] < 0.05]
    survive = sum(adjusted[i] < 0.05 for i in uncorrected)
    lines = [
        f"{heading} {title}",
        "",
        f"{len(family)} differences are tested here (the family). Excluding zero at 95 %: "
        f"{len(uncorrected)} uncorrected, **{survive} after Holm's correction** (family-wise "
        "error 5 %, `realikea.eval.stats.holm`; p-values agree with the intervals: Newcombe's "
        "with one seed a side, the seed bootstrap's otherwise, resolution 1e-4).",
    ]
    if uncorrected:
        lines += [
            "",
            "| difference | a − b [95 %] | p | Holm-adjusted p | after correction |",
            "|---|---|---:|---:|---|",
        ]
    for i in uncorrected:
        d, lo, hi = family[i].interval()
        verdict = "significant" if adjusted[i] < 0.05 else "not significant"
        lines.append(
            f"| {family[i].label} | {d:+.2f} [{lo:+.2f}, {hi:+.2f}] | {_p(ps[i])} | "
            f"{_p(adjusted[i])} | {verdict} |"
        )
    return lines


def _p(value: float) -> str:
    return "< 0.0001" if value < 1e-4 else f"{value:.4f}"
