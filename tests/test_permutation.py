"""Exact permutation tests over policies (realikea/eval/permutation.py), checked by hand."""

from __future__ import annotations

import math

import pytest

from realikea.eval.permutation import (
    permutation_p,
    shift_interval,
    stratified_difference,
    stratified_permutation_p,
)


def test_fully_separated_groups_reach_the_smallest_p_of_their_sizes():
    assert permutation_p([1.0, 0.9, 0.8], [0.1, 0.0, 0.2]) == pytest.approx(2 / 20)
    assert permutation_p([1, 0.9, 0.8, 0.7, 0.6], [0.1, 0, 0.2, 0.3, 0.4]) == pytest.approx(2 / 252)
    assert permutation_p([0.5, 0.5], [0.5, 0.5]) == 1.0


def test_two_strata_of_one_policy_a_side_by_hand():
    # assignments: (+1, +1), (+1, -1), (-1, +1), (-1, -1); |mean| >= 1 in two of four
    assert stratified_permutation_p([([1.0], [0.0]), ([1.0], [0.0])]) == pytest.approx(0.5)


def test_stratifying_permutes_within_a_category_only():
    # each category's four policies split 2 / 2 (6 ways each, 36 in all); only the two
    # assignments separating both categories the same way reach the observed +0.2
    strata = [([0.9, 0.8], [0.7, 0.6]), ([0.3, 0.2], [0.1, 0.0])]
    assert stratified_difference(strata) == pytest.approx(0.2)
    assert stratified_permutation_p(strata) == pytest.approx(2 / 36)
    pooled = permutation_p([0.9, 0.8, 0.3, 0.2], [0.7, 0.6, 0.1, 0.0])
    assert pooled > 0.3  # pooled, the category's level swamps the difference


def test_the_interval_excludes_zero_exactly_where_p_is_below_five_percent():
    a, b = [0.9, 0.8, 0.85, 0.7, 0.95], [0.2, 0.3, 0.1, 0.4, 0.25]
    low, high = shift_interval([(a, b)])
    assert permutation_p(a, b) < 0.05 and 0 < low < 0.64 < high < 1
    # the shift's ends: a - low against b is not rejected, a little below low it is
    assert permutation_p([v - low for v in a], b) >= 0.05
    assert permutation_p([v - low + 0.01 for v in a], b) < 0.05
    close = ([0.5, 0.6, 0.4, 0.55, 0.45], [0.5, 0.4, 0.6, 0.52, 0.48])
    low, high = shift_interval([close])
    assert permutation_p(*close) >= 0.05 and low < 0 < high


def test_three_policies_a_side_cannot_reject_any_shift():
    assert shift_interval([([1.0, 1.0, 1.0], [0.0, 0.0, 0.0])]) == (-math.inf, math.inf)


@pytest.mark.parametrize(
    "strata, message",
    [
        ([], "no strata"),
        ([([], [0.1])], "at least one policy"),
        ([([math.nan], [0.1])], "finite"),
        ([([0.5] * 12, [0.5] * 12)] * 2, "too many"),
    ],
)
def test_bad_input_is_refused(strata, message):
    with pytest.raises(ValueError, match=message):
        stratified_permutation_p(strata)
