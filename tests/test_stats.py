"""Wilson and Newcombe intervals (realikea/eval/stats.py) against published values; p-values
that agree with them; Holm's correction."""

from __future__ import annotations

from statistics import NormalDist

import pytest

from realikea.eval.stats import (
    count,
    diff_interval,
    diff_p,
    holm,
    main,
    seed_difference,
    seed_difference_p,
    seed_interval,
    seed_permutation_p,
    significant,
    wilson,
)


def test_wilson_known_values():
    assert wilson(5, 10) == pytest.approx((0.2366, 0.7634), abs=1e-4)
    assert wilson(0, 10) == pytest.approx((0.0, 0.2775), abs=1e-4)
    assert wilson(10, 10) == pytest.approx((0.7225, 1.0), abs=1e-4)
    assert wilson(81, 263) == pytest.approx((0.2553, 0.3662), abs=1e-4)


def test_newcombe_difference_known_values():
    # Newcombe (1998), method 10: 56/70 - 48/80 = 0.200, interval (0.0524, 0.3339)
    assert diff_interval(56, 70, 48, 80) == pytest.approx((0.0524, 0.3339), abs=1e-4)
    assert significant(56, 70, 48, 80)
    # the cross-evaluation's seed 2 under pyramidal cones: 0.46 vs 0.32 of 50
    lo, hi = diff_interval(23, 50, 16, 50)
    assert lo < 0 < hi and not significant(23, 50, 16, 50)


def test_bad_input_and_counts(capsys):
    with pytest.raises(ValueError):
        wilson(3, 2)
    assert count(0.46, 50) == 23
    with pytest.raises(ValueError):
        count(0.333, 50)
    assert main(["23/50", "16/50"]) == 0
    assert "not significant" in capsys.readouterr().out


def test_seed_bootstrap_on_known_inputs():
    # every episode of every seed a success: no spread at all
    assert seed_interval([(50, 50)] * 3) == (1.0, 1.0, 1.0)
    # one seed: the episodes' spread only, close to Wilson's for 25/50 (0.37, 0.63)
    mean, lo, hi = seed_interval([(25, 50)])
    assert (
        mean == 0.5 and lo == pytest.approx(0.36, abs=0.03) and hi == pytest.approx(0.64, abs=0.03)
    )
    # seeds that disagree widen the interval beyond what the episodes alone give
    _, lo3, hi3 = seed_interval([(5, 50), (25, 50), (45, 50)])
    _, lo1, hi1 = seed_interval([(75, 150)])
    assert hi3 - lo3 > 2 * (hi1 - lo1)
    # the same seed gives the same interval
    assert seed_interval([(5, 50), (45, 50)], seed=3) == seed_interval([(5, 50), (45, 50)], seed=3)


def test_seed_difference_on_known_inputs():
    d, lo, hi = seed_difference([(45, 50)] * 3, [(5, 50)] * 3)
    assert d == pytest.approx(0.8) and 0.6 < lo < hi < 1.0  # clearly apart
    d, lo, hi = seed_difference([(20, 50), (30, 50)], [(30, 50), (20, 50)])
    assert d == 0.0 and lo < 0 < hi  # the same runs: not significant
    with pytest.raises(ValueError):
        seed_difference([], [(1, 2)])
    with pytest.raises(ValueError):
        seed_interval([(3, 2)])


def test_p_values_agree_with_the_intervals():
    for k1, n1, k2, n2 in [(23, 50, 16, 50), (18, 50, 1, 50), (30, 50, 20, 50), (5, 20, 9, 20)]:
        lo, hi = diff_interval(k1, n1, k2, n2)
        assert (diff_p(k1, n1, k2, n2) < 0.05) == (lo > 0 or hi < 0)
        # at the p-value's own level the interval just reaches zero
        z = NormalDist().inv_cdf(1 - diff_p(k1, n1, k2, n2) / 2)
        assert min(abs(x) for x in diff_interval(k1, n1, k2, n2, z)) < 1e-6
    assert diff_p(10, 50, 10, 50) == 1.0
    a, b = [(45, 50), (40, 50), (44, 50)], [(20, 50), (30, 50), (12, 50)]
    _, lo, _ = seed_difference(a, b)
    assert lo > 0 and seed_difference_p(a, b) < 0.05
    a, b = [(45, 50), (5, 50)], [(30, 50), (20, 50)]
    _, lo, hi = seed_difference(a, b)
    assert lo < 0 < hi and seed_difference_p(a, b) > 0.05


def test_the_seed_permutation_test_by_hand():
    # three seeds a side, every CoACD seed above every hull seed: of the C(6, 3) = 20 splits of
    # the six rates only the observed one and its mirror reach |0.8 - 0.1| = 0.7, so p = 2 / 20
    a, b = [(45, 50), (40, 50), (35, 50)], [(5, 50), (10, 50), (0, 50)]
    assert seed_permutation_p(a, b) == pytest.approx(0.1)
    assert seed_permutation_p(b, a) == pytest.approx(0.1)  # two-sided
    # rates 1.0, 0.5 against 0.0, 0.5: observed |0.75 - 0.25| = 0.5; of the 6 splits
    # {1.0, 0.5}, {1.0, 0.5'}, {0.0, 0.5}, {0.0, 0.5'} reach 0.5, {1.0, 0.0}, {0.5, 0.5'} give 0
    assert seed_permutation_p([(10, 10), (5, 10)], [(0, 10), (5, 10)]) == pytest.approx(4 / 6)
    # four seeds a side, fully separated: 2 / C(8, 4) = 2 / 70 < 0.05
    four = seed_permutation_p([(9, 10)] * 2 + [(8, 10)] * 2, [(1, 10), (2, 10)] * 2)
    assert four == pytest.approx(2 / 70)
    assert seed_permutation_p([(5, 10)], [(5, 10)]) == 1.0
    with pytest.raises(ValueError):
        seed_permutation_p([], [(5, 10)])


def test_holm_adjusts_step_down_and_keeps_the_order():
    # sorted: 0.005 x 4, 0.01 x 3, 0.03 x 2, 0.04 x 1, each at least the one before
    assert holm([0.01, 0.04, 0.03, 0.005]) == pytest.approx([0.03, 0.06, 0.06, 0.02])
    assert holm([0.5, 0.9]) == [1.0, 1.0] and holm([]) == []
    # one difference among many: significant alone, not in a family of 40
    assert holm([0.01] + [0.5] * 39)[0] > 0.05
