"""Which finger pulls the policies open against the room behind their lip
(experiments/generalist/finger_pull_parts.py): the pooling, the narrow / wide split at the pad's
thickness, and a run with no records refused before anything is written."""

from __future__ import annotations

import json

import pytest

# channel, drop (m): one narrower than the 9 mm pad, one wider
ROOMS = {"fp_edge_128": (0.0061, 0.008), "fp_cup_160": (0.016, 0.042)}


@pytest.fixture
def parts(load_script, monkeypatch):
    module = load_script("experiments/generalist/finger_pull_parts.py")
    monkeypatch.setattr(module, "room", lambda part, library: ROOMS[part])
    return module


def write_episodes(run, mode, outcomes, validation=True):
    (run / "misses").mkdir(parents=True, exist_ok=True)
    draw = "_validation" if validation else ""
    lines = [json.dumps({"part": part, "outcome": outcome}) for part, outcome in outcomes]
    (run / "misses" / f"finger_pull_door_{mode}{draw}.jsonl").write_text("\n".join(lines) + "\n")


def test_parts_are_pooled_over_runs_and_modes_and_split_at_the_pads_thickness(parts, tmp_path):
    s0, s1 = tmp_path / "default/s0", tmp_path / "default/s1"
    write_episodes(s0, "smooth", [("fp_edge_128", "fail"), ("fp_cup_160", "success")])
    write_episodes(s0, "high", [("fp_edge_128", "partial"), ("fp_cup_160", "success")])
    write_episodes(s1, "smooth", [("fp_edge_128", "success"), ("fp_cup_160", "fail")])
    write_episodes(s1, "high", [("fp_cup_160", "success")], validation=False)  # the test draw
    assert parts.main([str(s0), str(s1), "--kind", "door", "--validation"]) == 0
    text = (tmp_path / "default/finger_pull_door_parts_validation.md").read_text()
    assert "| fp_edge_128 | train | 6.1 | 8.0 | 3 | 1 (0.33) | 1 | 1 |" in text
    assert "| fp_cup_160 | train | 16.0 | 42.0 | 3 | 2 (0.67) | 0 | 1 |" in text
    assert text.index("| fp_edge_128 |") < text.index("| fp_cup_160 |")  # by channel
    assert "| channel < 9 mm | channel ≥ 9 mm |" in text
    assert f"| {s0} | smooth | 0 / 1 | 1 / 1 |" in text
    assert f"| {s1} | smooth | 1 / 1 | 0 / 1 |" in text
    assert f"| {s1} | high |" not in text  # a test-draw record is not on the validation draw


def test_a_run_with_no_records_is_refused_before_anything_is_written(parts, tmp_path, capsys):
    s0, s1 = tmp_path / "default/s0", tmp_path / "default/s1"
    write_episodes(s0, "smooth", [("fp_cup_160", "success")])
    s1.mkdir(parents=True)
    with pytest.raises(SystemExit) as exit_:
        parts.main([str(s0), str(s1), "--kind", "door", "--validation"])
    assert exit_.value.code == 2
    assert "misses.py --validation) in:" in capsys.readouterr().err
    assert not list((tmp_path / "default").glob("*.md"))
