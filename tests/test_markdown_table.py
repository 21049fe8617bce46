"""The shared markdown table: header, rule from the alignment, a line per row; a row or an
alignment that does not fit the header is refused."""

from __future__ import annotations

import pytest

from realikea.markdown import table


def test_a_table_has_its_header_rule_and_rows():
    assert table(["run", "success"], "lr", [["a", "0.50"], ["b", "1.00"]]) == [
        "| run | success |",
        "|---|---:|",
        "| a | 0.50 |",
        "| b | 1.00 |",
    ]


@pytest.mark.parametrize(
    ("align", "rows", "message"),
    [("l", [], "align 'l' names 1 columns"), ("lr", [["a"]], "a row of 1 cells under 2")],
)
def test_a_misfit_row_or_alignment_is_refused(align, rows, message):
    with pytest.raises(ValueError, match=message):
        table(["run", "success"], align, rows)
