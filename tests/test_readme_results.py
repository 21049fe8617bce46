"""The README's Results stay a short table: at most 10 rows of at most 40 words each (the caveats
and details live in docs/results.md)."""

from __future__ import annotations

import re

from realikea.files import WORKSPACE

MAX_ROWS = 10
MAX_WORDS = 40
LINK_TARGET = re.compile(r"\]\([^)]*\)")  # a link's target: its text counts, its address not
WORD = re.compile(r"[^\W_]")  # a token counts as a word if it holds a letter or a digit


def results_rows(text: str) -> list[str]:
    """The body rows of the first table in the README's `## Results` section."""
    section = text.split("\n## Results\n", 1)[1].split("\n## ", 1)[0]
    table = [line for line in section.splitlines() if line.startswith("|")]
    assert len(table) >= 2 and set(table[1]) <= set("|-: "), "no markdown table under Results"
    return table[2:]


def words(row: str) -> int:
    """Words of a table row: whitespace-separated tokens with a letter or digit, the cells'
    bars and a link's address left out."""
    return sum(bool(WORD.search(token)) for token in LINK_TARGET.sub("]", row).split())


def test_words_are_counted_without_link_targets_and_bars():
    assert words("| one claim | holds | 0.5 [0.4, 0.6] | [link](docs/results.md#a-b) |") == 7
    assert words("| a → b − c | |") == 3


def test_the_readme_results_are_a_short_table():
    rows = results_rows((WORKSPACE / "README.md").read_text())
    assert 1 <= len(rows) <= MAX_ROWS, f"{len(rows)} rows under Results (at most {MAX_ROWS})"
    long = {row[:60]: words(row) for row in rows if words(row) > MAX_WORDS}
    assert not long, f"rows over {MAX_WORDS} words: {long}"
    columns = "claim | verdict | figure | link"
    assert all(row.count("|") - row.count("\\|") == 5 for row in rows), columns
