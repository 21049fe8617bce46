"""Two kept runs' cells side by side (experiments/generalist/compare_cells.py)."""

from __future__ import annotations

import json

import pytest


@pytest.fixture
def compare(load_script):
    return load_script("experiments/generalist/compare_cells.py")


def write_cells(path, rates: dict):
    path.mkdir(parents=True, exist_ok=True)
    lines = []
    for (kind, category, mode), success in rates.items():
        where = {"kind": kind, "category": category, "resistance": mode, "episodes": 50}
        lines.append(json.dumps(where | {"success": success, "fail": 1 - success, "partial": 0.0}))
    (path / "validation_cells.jsonl").write_text("\n".join(lines) + "\n")


def test_the_mean_difference_is_over_the_cells_both_runs_have(compare, tmp_path, capsys):
    a, b = tmp_path / "a", tmp_path / "b"
    write_cells(a, {("door", "knob", "smooth"): 0.9, ("door", "knob", "high"): 0.8,
                    ("flap", "knob", "high"): 1.0})  # fmt: skip
    write_cells(b, {("door", "knob", "smooth"): 0.7, ("door", "knob", "high"): 0.8})
    assert compare.main([str(a), str(b), "--validation"]) == 0
    out = capsys.readouterr().out
    assert "mean difference A − B over the 2 cells both have: +0.10" in out
    assert "0.90 / 0.70, +0.20" in out  # the knob doors in smooth, with their interval


def test_a_run_without_the_cells_is_refused(compare, tmp_path, capsys):
    write_cells(tmp_path / "a", {("door", "knob", "smooth"): 0.9})
    with pytest.raises(SystemExit) as exit_:
        compare.main([str(tmp_path / "a"), str(tmp_path / "b"), "--validation"])
    assert exit_.value.code == 2
    assert "b/validation_cells.jsonl" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        compare.main([str(tmp_path / "a"), str(tmp_path / "a")])  # no test-draw cells.jsonl
