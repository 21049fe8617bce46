"""Numbers the READMEs quote from data files match the data (`realikea/reports/quotes.py`)."""

from __future__ import annotations

import json

import pytest

from realikea.files import WORKSPACE
from realikea.reports.quotes import check, lookup, quotes, written


@pytest.mark.parametrize(
    ("value", "text", "expected"),
    [
        (0.8236, "0.82", "0.82"),
        (0.8651, "87 %", "87%"),
        (0.0891, "8.9%", "8.9%"),
        (1316.2, "1,316", "1,316"),
        (-0.23, "−0.23", "−0.23"),
        (-0.23, "+0.23", "-0.23"),
        (0.21, "+0.21", "+0.21"),
        (-0.001, "0.00", "0.00"),
        (1.0, "n/a", None),
    ],
)
def test_a_value_is_written_as_the_quote_writes_it(value, text, expected):
    assert written(value, text) == expected


def test_a_key_walks_dicts_and_picks_list_items_by_a_field():
    data = {
        "rates": [{"envs": 1, "pool": 804.0}, {"envs": 32, "pool": 1206.0, "way": "pool"}],
        "a": {"b": 2},
    }
    assert lookup(data, "rates.envs=32.pool") == 1206.0
    assert lookup(data, "a.b") == 2
    assert lookup(data, "rates.1.envs") == 32
    assert lookup(data, "rates.envs=32&way=pool.pool") == 1206.0
    with pytest.raises(KeyError):
        lookup(data, "rates.envs=64.pool")


def test_a_wrong_number_a_missing_key_and_a_missing_file_are_named(tmp_path):
    (tmp_path / "cells.json").write_text(
        json.dumps({"rate": 0.823, "n": 50, "ci": [0.9, 0.7912, 0.9568]})
    )
    (tmp_path / "rows.csv").write_text("cell,success\na,0.5\nb,0.25\n")
    md = tmp_path / "README.md"
    md.write_text(
        'ok [0.82](cells.json "rate"), [0.25](rows.csv "cell=b.success"), '
        '[0.90 [0.79, 0.96]](cells.json "ci");\n'
        'wrong [0.83](cells.json "rate"), [50](cells.json "runs"), [1](gone.json "x"), '
        '[0.90 [0.80, 0.96]](cells.json "ci")\n'
    )
    md.write_text(
        md.read_text() + 'code `[1](gone.json "x")` and\n\n    [1](gone.json "x")\n'
        '```\n[1](gone.json "x")\n```\n'
    )
    assert len(quotes(md)) == 7  # none of the three in code
    problems = check([md])
    assert len(problems) == 4
    assert "README.md:2" in problems[0] and "the data say 0.82" in problems[0]
    assert "key not found" in problems[1]
    assert "no file" in problems[2]
    assert "the data say 0.90 [0.79, 0.96]" in problems[3]


def test_every_quoted_number_in_the_docs_matches_its_data():
    files = [
        WORKSPACE / "README.md",
        WORKSPACE / "DATASET.md",
        *sorted((WORKSPACE / "docs").rglob("*.md")),
        *sorted((WORKSPACE / "experiments").rglob("*.md")),
    ]
    assert sum(len(quotes(f)) for f in files) > 0
    assert check(files) == []
