"""Confidence intervals for success rates: Wilson's score interval for one proportion,
Newcombe's hybrid score interval for the difference of two independent ones, and a two-level
bootstrap (seeds, then episodes) for the mean rate of several training seeds and for the
difference of two such means; each difference's two-sided p-value (the level at which its
interval reaches zero), an exact permutation test over seeds for a difference of several seeds
a side (the seed the unit, `seed_permutation_p`), and Holm's step-down correction for a family
of them.

    python -m realikea.eval.stats 23/50 16/50     # each rate's interval, then their difference

Newcombe (1998), "Interval estimation for the difference between independent proportions",
method 10: the difference's interval from the two Wilson intervals. It is well-behaved at 0 and
1 (unlike the Wald interval) and is what "the intervals overlap / the difference's interval
includes zero" below refers to. Holm (1979), "A simple sequentially rejective multiple test
procedure": the family-wise error stays at 5 % however many differences a report tests.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence

import numpy as np

from realikea.eval.permutation import permutation_p

Z95 = 1.959963984540054  # the standard normal's 97.5 % quantile


def _check(k: int, n: int) -> None:
    if n < 1 or not 0 <= k <= n:
        raise ValueError(f"need 0 <= k <= n and n >= 1, got k={k}, n={n}")


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson's score interval for k successes in n trials (95 % by default)."""
    _check(k, n)
    p = k / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return max(0.0, centre - half), min(1.0, centre + half)


def diff_interval(k1: int, n1: int, k2: int, n2: int, z: float = Z95) -> tuple[float, float]:
    """Newcombe's interval for p1 - p2 from the two Wilson intervals (95 % by default)."""
    (l1, u1), (l2, u2) = wilson(k1, n1, z), wilson(k2, n2, z)
    p1, p2 = k1 / n1, k2 / n2
    d = p1 - p2
    return (
        d - math.sqrt((p1 - l1) ** 2 + (u2 - p2) ** 2),
        d + math.sqrt((u1 - p1) ** 2 + (p2 - l2) ** 2),
    )


def significant(k1: int, n1: int, k2: int, n2: int, z: float = Z95) -> bool:
    """Whether the difference's interval excludes zero."""
    lo, hi = diff_interval(k1, n1, k2, n2, z)
    return lo > 0 or hi < 0


def diff_p(k1: int, n1: int, k2: int, n2: int) -> float:
    """Two-sided p-value of p1 - p2 that agrees with Newcombe's interval: the level at which
    the interval reaches zero (its z found by bisection), so p < 0.05 exactly where the 95 %
    interval excludes zero."""
    if k1 * n2 == k2 * n1:
        return 1.0
    inside, outside = 0.0, 40.0  # excludes zero at z = 0 (a point), includes it as z grows
    if significant(k1, n1, k2, n2, outside):
        return 0.0
    for _ in range(60):
        z = (inside + outside) / 2
        inside, outside = (z, outside) if significant(k1, n1, k2, n2, z) else (inside, z)
    return math.erfc(outside / math.sqrt(2))


def holm(pvalues: Sequence[float]) -> list[float]:
    """Holm's step-down adjusted p-values, in the order given: a difference is significant with
    the family-wise error at 5 % where its adjusted p-value is below 0.05."""
    order = sorted(range(len(pvalues)), key=lambda i: pvalues[i])
    adjusted = [1.0] * len(pvalues)
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (len(pvalues) - rank) * pvalues[i]))
        adjusted[i] = running
    return adjusted


BOOTSTRAP_DRAWS = 10_000


def _seed_means(runs: Sequence[tuple[int, int]], rng: np.random.Generator, draws: int):
    """`draws` bootstrap replicates of the mean rate over seeds: seeds drawn with replacement,
    then each drawn seed's episodes redrawn (binomially at its own rate)."""
    for k, n in runs:
        _check(k, n)
    k = np.array([r[0] for r in runs], float)
    n = np.array([r[1] for r in runs], int)
    picks = rng.integers(0, len(runs), size=(draws, len(runs)))
    return (rng.binomial(n[picks], k[picks] / n[picks]) / n[picks]).mean(axis=1)


def seed_interval(
    runs: Sequence[tuple[int, int]], seed: int = 0, draws: int = BOOTSTRAP_DRAWS
) -> tuple[float, float, float]:
    """(mean, low, high): the mean success rate of several runs (k successes of n episodes
    each, one run a training seed) with a 95 % percentile-bootstrap interval over seeds and
    episodes. With one run only episodes vary: the interval then says nothing of other seeds."""
    if not runs:
        raise ValueError("no runs")
    rates = _seed_means(runs, np.random.default_rng(seed), draws)
    lo, hi = np.percentile(rates, [2.5, 97.5])
    return float(np.mean([k / n for k, n in runs])), float(lo), float(hi)


def seed_difference(
    a: Sequence[tuple[int, int]],
    b: Sequence[tuple[int, int]],
    seed: int = 0,
    draws: int = BOOTSTRAP_DRAWS,
) -> tuple[float, float, float]:
    """(difference, low, high) of the mean rates of two independent groups of runs (mean of a
    minus mean of b), with the 95 % bootstrap interval of `seed_interval`'s two levels."""
    diffs = _difference_draws(a, b, seed, draws)
    lo, hi = np.percentile(diffs, [2.5, 97.5])
    d = np.mean([k / n for k, n in a]) - np.mean([k / n for k, n in b])
    return float(d), float(lo), float(hi)


def seed_difference_p(
    a: Sequence[tuple[int, int]],
    b: Sequence[tuple[int, int]],
    seed: int = 0,
    draws: int = BOOTSTRAP_DRAWS,
) -> float:
    """Two-sided p-value of `seed_difference` (same draws): twice the share of bootstrap
    differences on the far side of zero, so p < 0.05 where its percentile interval excludes
    zero. Its resolution is 1 / `draws`."""
    diffs = _difference_draws(a, b, seed, draws)
    return float(min(1.0, 2 * min(np.mean(diffs <= 0), np.mean(diffs >= 0))))


def seed_permutation_p(a: Sequence[tuple[int, int]], b: Sequence[tuple[int, int]]) -> float:
    """Two-sided p-value of the difference of two groups' mean rates with the training seed as
    the unit (k successes of n episodes a run, one run a seed): an exact permutation test over
    the runs' rates. Under no difference every split of the pooled runs into groups of the two
    sizes is equally likely; p is the share of the splits whose |mean a - mean b| reaches the
    observed one. Its smallest value is 2 / C(len(a) + len(b), len(a)): 0.10 with three seeds a
    side, 0.029 with four, so three seeds a side can never give p < 0.05."""
    if not a or not b:
        raise ValueError("both groups need at least one run")
    for k, n in (*a, *b):
        _check(k, n)
    return permutation_p([k / n for k, n in a], [k / n for k, n in b])


def _difference_draws(a, b, seed: int, draws: int) -> np.ndarray:
    if not a or not b:
        raise ValueError("both groups need at least one run")
    rng = np.random.default_rng(seed)
    return _seed_means(a, rng, draws) - _seed_means(b, rng, draws)


def count(rate: float, n: int) -> int:
    """Successes behind a rate printed to two decimals over n episodes (0.46 of 50 -> 23)."""
    k = round(rate * n)
    if abs(k / n - rate) > 0.005 + 1e-9:
        raise ValueError(f"{rate} is not a count out of {n}")
    return k


def describe(k: int, n: int) -> str:
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}]"


def main(argv: list[str]) -> int:
    """Print the Wilson interval of each K/N, and Newcombe's for the first two's difference."""
    if not argv or any("/" not in a for a in argv):
        print("usage: python -m realikea.eval.stats K/N [K/N ...]", file=sys.stderr)
        return 2
    pairs = [tuple(int(x) for x in a.split("/")) for a in argv]
    for k, n in pairs:
        print(describe(k, n))
    if len(pairs) >= 2:
        (k1, n1), (k2, n2) = pairs[:2]
        lo, hi = diff_interval(k1, n1, k2, n2)
        verdict = "significant" if significant(k1, n1, k2, n2) else "not significant"
        print(f"difference {k1 / n1 - k2 / n2:+.2f} [{lo:+.2f}, {hi:+.2f}]: {verdict}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
