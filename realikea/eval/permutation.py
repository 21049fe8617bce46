"""Exact permutation tests with the training seed as the unit: one value per policy (a success
rate, a strategy's share of successes), two groups of policies, optionally within strata (a
category each), and the interval of shifts the test does not reject.

Under no difference every assignment of a stratum's pooled policies to the two groups (sizes
kept) is equally likely; a stratified test permutes within each stratum only. The statistic is
the mean over strata of (mean of a - mean of b); p is the share of assignments whose |statistic|
reaches the observed one (two-sided, exact: every assignment is enumerated).

The interval inverts the test under a shift model (a's values = b's + delta): it holds every
delta at which the test of (a - delta) against b gives p >= ALPHA, so it excludes zero exactly
where p < ALPHA. With three policies a side the smallest p is 0.10, so no shift is rejected and
the interval is unbounded: three seeds a side cannot call a difference at 5 %.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np

ALPHA = 0.05
MAX_ASSIGNMENTS = 5_000_000  # beyond this an exact test would not fit in memory
SHIFT_STEP = 0.001  # resolution of the interval's ends
_TIE = 1e-12  # a permuted statistic this close to the observed one reaches it

Stratum = tuple[Sequence[float], Sequence[float]]  # (values of a, values of b)


def _assignments(n: int, m: int) -> np.ndarray:
    """Every way of choosing m of n policies as group a: a (C(n, m), n) 0/1 matrix."""
    rows = list(itertools.combinations(range(n), m))
    chosen = np.zeros((len(rows), n))
    for r, picked in enumerate(rows):
        chosen[r, list(picked)] = 1.0
    return chosen


def _check(strata: Sequence[Stratum]) -> None:
    if not strata:
        raise ValueError("no strata")
    size = 1
    for a, b in strata:
        if len(a) == 0 or len(b) == 0:
            raise ValueError("both groups need at least one policy in every stratum")
        if not all(math.isfinite(v) for v in (*a, *b)):
            raise ValueError(f"values must be finite, got {list(a)} and {list(b)}")
        size *= math.comb(len(a) + len(b), len(a))
    if size > MAX_ASSIGNMENTS:
        raise ValueError(f"{size} assignments: too many for an exact test")


class _Stratum:
    """One stratum's assignments and the a-membership of its pooled policies."""

    def __init__(self, a: Sequence[float], b: Sequence[float]):
        self.values = np.array([*a, *b], dtype=float)
        self.in_a = np.r_[np.ones(len(a)), np.zeros(len(b))]
        self.m, self.n = len(a), len(a) + len(b)
        self.chosen = _assignments(self.n, self.m)

    def statistics(self, shift: float) -> np.ndarray:
        """Mean of a - mean of b for every assignment, a's values first lowered by `shift`."""
        values = self.values - shift * self.in_a
        inside = self.chosen @ values
        return inside / self.m - (values.sum() - inside) / (self.n - self.m)

    def observed(self, shift: float) -> float:
        values = self.values - shift * self.in_a
        return float(values[: self.m].mean() - values[self.m :].mean())


def _p(strata: list[_Stratum], shift: float) -> float:
    observed = np.mean([s.observed(shift) for s in strata])
    total = np.zeros(1)
    for s in strata:  # every combination of the strata's assignments, summed
        total = (total[:, None] + s.statistics(shift)[None, :]).ravel()
    total /= len(strata)
    return float(np.mean(np.abs(total) >= abs(observed) - _TIE))


def stratified_permutation_p(strata: Sequence[Stratum]) -> float:
    """Two-sided exact p of the mean over strata of (mean a - mean b), permuting within strata."""
    _check(strata)
    return _p([_Stratum(a, b) for a, b in strata], 0.0)


def permutation_p(a: Sequence[float], b: Sequence[float]) -> float:
    """Two-sided exact p of mean a - mean b, one value per policy (one stratum)."""
    return stratified_permutation_p([(a, b)])


def stratified_difference(strata: Sequence[Stratum]) -> float:
    """The statistic: the mean over strata of (mean a - mean b)."""
    _check(strata)
    return float(np.mean([np.mean(a) - np.mean(b) for a, b in strata]))


def shift_interval(strata: Sequence[Stratum], alpha: float = ALPHA) -> tuple[float, float]:
    """(low, high): every shift the stratified test does not reject at `alpha` (p >= alpha),
    on a grid of SHIFT_STEP; -inf / inf where no shift in reach is rejected on that side."""
    _check(strata)
    built = [_Stratum(a, b) for a, b in strata]
    spread = max(float(np.ptp(s.values)) for s in built)
    reach = math.ceil(spread / SHIFT_STEP) + 2
    grid = np.arange(-reach, reach + 1) * SHIFT_STEP
    kept = [shift for shift in grid if _p(built, shift) >= alpha]
    if not kept:  # only with ties at every shift; never for a point estimate itself
        raise ValueError("every shift is rejected")
    low = -math.inf if kept[0] == grid[0] else float(kept[0])
    high = math.inf if kept[-1] == grid[-1] else float(kept[-1])
    return low, high
