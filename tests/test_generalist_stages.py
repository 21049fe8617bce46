"""The staged run's timeline (experiments/generalist/stages.py): each stage's times relative to
the first stage's start, and how many stages trained at once on average."""

from __future__ import annotations

import json

import pytest


@pytest.fixture
def stages(load_script):
    return load_script("experiments/generalist/stages.py")


def stage(name, began, ended, iterations=400, resumed_at=0):
    return {"name": name, "iterations": iterations, "resumed_at": resumed_at,
            "seconds": ended - began, "began": began, "ended": ended,
            "success": {"knob_door": 0.9}}  # fmt: skip


def test_two_stages_side_by_side_then_one_show_their_overlap(stages, tmp_path, capsys):
    records = [stage("teacher_door", 1000, 2200), stage("teacher_flap", 1000, 1600),
               stage("student", 2200, 2800, iterations=200, resumed_at=100)]  # fmt: skip
    records[-1]["teachers"] = {"knob_door": "teacher_door", "knob_flap": "teacher_flap"}
    records[0]["validation"] = {"knob_door": 0.78}  # judged on the validation draw
    records[1]["validation"] = {"knob_flap": 0.92, "two_point_flap": 0.90}
    records[1]["validation_high"] = {"knob_flap": 0.76, "two_point_flap": 0.70}  # also in high
    (tmp_path / "stages.json").write_text(json.dumps(records))
    assert stages.main([str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "student's teachers: knob_door from teacher_door, knob_flap from teacher_flap" in out
    assert (
        "| teacher_flap | 0.0 | 10.0 | 10.0 | 400 | 1.50 | 0 | knob_door 0.90 | knob_flap 0.92"
        " / high 0.76, two_point_flap 0.90 / high 0.70 |"
    ) in out
    assert "| student | 20.0 | 30.0 | 10.0 | 200 | 6.00 | 100 | knob_door 0.90 | – |" in out
    assert "| 0 | knob_door 0.90 | knob_door 0.78 |" in out  # the door teacher's
    assert "| student | 20.0 | 30.0 | 10.0 | 200 | 6.00 | 100 |" in out
    # 40 stage-minutes in a 30-minute span
    assert "span 30.0 min" in out and "stages' minutes summed 40.0; 1.33 at once" in out


def test_a_gap_between_launches_is_not_counted_as_training(stages, tmp_path, capsys):
    """A parked run: its last stages resumed an hour after the first ended."""
    records = [stage("teacher_drawer", 0, 600), stage("teacher_door", 4200, 4800, resumed_at=200),
               stage("teacher_flap", 4500, 5400)]  # fmt: skip
    (tmp_path / "stages.json").write_text(json.dumps(records))
    assert stages.main([str(tmp_path)]) == 0
    out = capsys.readouterr().out
    # 35 stage-minutes while some stage trained: 10 + 20 of a 90-minute span
    assert "span 90.0 min" in out and "30.0 min of it with a stage training" in out
    assert "stages' minutes summed 35.0; 1.17 at once" in out


def test_a_folder_without_stages_is_refused(stages, tmp_path, capsys):
    assert stages.main([str(tmp_path)]) == 2
    assert "no stages.json in" in capsys.readouterr().err
