"""Wilson and Newcombe intervals (realikea/eval/stats.py) against published values."""

from __future__ import annotations

import pytest

from realikea.eval.stats import count, diff_interval, main, significant, wilson


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
