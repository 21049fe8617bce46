"""Holm's correction over a report's family of differences (realikea/reports/multiplicity.py)."""

from __future__ import annotations

import pytest

from realikea.reports.multiplicity import Difference, holm_lines


def test_a_difference_significant_alone_need_not_survive_its_family():
    strong = Difference("strong", [(45, 50)], [(10, 50)])  # p < 1e-4
    weak = Difference("weak", [(30, 50)], [(20, 50)])  # p = 0.045 alone
    nulls = [Difference(f"null {i}", [(25, 50)], [(25, 50)]) for i in range(8)]
    lines = holm_lines([strong, weak, *nulls], "Family")
    text = "\n".join(lines)
    assert lines[0] == "## Family"
    assert "10 differences are tested here" in text
    assert "2 uncorrected, **1 after Holm's correction**" in text
    rows = [line for line in lines if line.startswith("| strong") or line.startswith("| weak")]
    assert rows[0].startswith("| strong") and rows[0].endswith("| significant |")
    assert rows[1].startswith("| weak") and rows[1].endswith("| not significant |")
    assert not any(line.startswith("| null") for line in lines)  # only those significant alone


def test_several_seeds_are_tested_at_the_seed_level_and_one_seed_by_newcombe():
    one = Difference("one", [(30, 50)], [(20, 50)])
    several = Difference("several", [(30, 50), (32, 50)], [(20, 50), (18, 50)])
    assert one.interval()[1:] != several.interval()[1:]
    assert 0 < one.p() < 0.05 and one.significant()
    # the bootstrap's interval excludes zero, but two seeds a side are 6 splits: p = 2 / 6
    assert several.interval()[1] > 0
    assert several.p() == pytest.approx(1 / 3) and not several.significant()
    lines = holm_lines([one, several], "Family")
    assert "Significant at 5 %: 1 uncorrected" in "\n".join(lines)
    assert "permutation test over the seeds" in "\n".join(lines)
