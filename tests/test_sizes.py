"""Sizes a reader can hold: no function over 80 lines in the package or the studies, and no study
script over 250 lines, except the ones listed here, each waiting for its own rewrite (the list
may only shrink)."""

from __future__ import annotations

LONGEST_FUNCTION, LONGEST_SCRIPT = 80, 250
LONG_FUNCTIONS: set[str] = set()
LONG_SCRIPTS: set[str] = set()


def test_no_function_is_longer_than_80_lines_but_the_listed(load_script):
    lengths = load_script("experiments/tools/sizes.py").function_lengths("realikea", "experiments")
    assert {name for name, lines in lengths.items() if lines > LONGEST_FUNCTION} == LONG_FUNCTIONS


def test_no_study_script_is_longer_than_250_lines_but_the_listed(load_script):
    lengths = load_script("experiments/tools/sizes.py").file_lengths("experiments")
    assert {name for name, lines in lengths.items() if lines > LONGEST_SCRIPT} == LONG_SCRIPTS
