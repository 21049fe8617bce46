"""Holm's correction over a report's family of differences: which stay significant when every
difference the report tests counts, not only the one quoted. A difference of one run a side is
tested on its episodes (Newcombe); one of several training seeds a side at the seed level, by an
exact permutation test over the seeds (the policy, not the episode, the unit)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from realikea.eval.stats import diff_interval, diff_p, holm, seed_difference, seed_permutation_p
from realikea.markdown import table

Runs = Sequence[tuple[int, int]]  # (count, episodes) per training seed


@dataclass(frozen=True)
class Difference:
    """One tested difference of two groups' rates (a minus b) and what names it."""

    label: str
    a: Runs
    b: Runs

    @property
    def several(self) -> bool:
        """Whether a side has more than one run (training seed)."""
        return len(self.a) > 1 or len(self.b) > 1

    def interval(self) -> tuple[float, float, float]:
        """(difference, low, high): Newcombe's with one run a side, else the seed bootstrap
        (descriptive: three seeds are no population to resample; `p` tests them)."""
        if not self.several:
            (k1, n1), (k2, n2) = self.a[0], self.b[0]
            return (k1 / n1 - k2 / n2, *diff_interval(k1, n1, k2, n2))
        return seed_difference(self.a, self.b)

    def p(self) -> float:
        """The two-sided p-value: with one run a side Newcombe's (p < 0.05 exactly where its
        interval excludes zero), else the exact permutation test over seeds."""
        if not self.several:
            (k1, n1), (k2, n2) = self.a[0], self.b[0]
            return diff_p(k1, n1, k2, n2)
        return seed_permutation_p(self.a, self.b)

    def significant(self) -> bool:
        """p < 0.05 (uncorrected), and never where the interval shown includes zero."""
        _, lo, hi = self.interval()
        return self.p() < 0.05 and (lo > 0 or hi < 0)


def holm_lines(family: Sequence[Difference], title: str, heading: str = "##") -> list[str]:
    """A Markdown section (`heading` title): the family's size, how many differences exclude
    zero before and after Holm's correction, and a row for each that does before it."""
    ps = [d.p() for d in family]
    adjusted = holm(ps)
    uncorrected = [i for i in np.argsort(ps, kind="stable") if family[i].significant()]
    survive = sum(adjusted[i] < 0.05 for i in uncorrected)
    if any(d.several for d in family):
        criterion = "Significant at 5 %"
        p_values = (
            "p-values: with one seed a side Newcombe's, agreeing with its interval; with "
            "several seeds a side an exact permutation test over the seeds, "
            "`realikea.eval.stats.seed_permutation_p`, whose smallest p is 0.10 with three "
            "seeds a side; their bootstrap interval is descriptive"
        )
    else:
        criterion = "Excluding zero at 95 %"
        p_values = (
            "p-values agree with the intervals: Newcombe's with one seed a side, the seed "
            "bootstrap's otherwise, resolution 1e-4"
        )
    how = (
        f"{len(family)} differences are tested here (the family). {criterion}: "
        f"{len(uncorrected)} uncorrected, **{survive} after Holm's correction** (family-wise "
        f"error 5 %, `realikea.eval.stats.holm`; {p_values})."
    )
    rows = []
    for i in uncorrected:
        d, lo, hi = family[i].interval()
        verdict = "significant" if adjusted[i] < 0.05 else "not significant"
        rows.append([family[i].label, f"{d:+.2f} [{lo:+.2f}, {hi:+.2f}]", _p(ps[i]),
                     _p(adjusted[i]), verdict])  # fmt: skip
    header = ["difference", "a − b [95 %]", "p", "Holm-adjusted p", "after correction"]
    lines = [f"{heading} {title}", "", how]
    return lines + (["", *table(header, "llrrl", rows)] if rows else [])


def _p(value: float) -> str:
    return "< 0.0001" if value < 1e-4 else f"{value:.4f}"
