"""The staged run's timeline (experiments/generalist/stages.py): each stage's times relative to
the first stage's start, and how many stages trained at once on average."""

from __future__ import annotations

import json

import pytest


@pytest.fixture
def stages(load_script):
    return load_script("experiments/generalist/stages.py")


def stage(name, began, ended, iterations=400, resumed_at=0, kind="", category="", starts_from=""):
    return {"name": name, "iterations": iterations, "resumed_at": resumed_at,
            "seconds": ended - began, "began": began, "ended": ended, "kind": kind,
            "category": category, "starts_from": starts_from,
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
    # which group teachers wait for their kind's is the run's config's to say
    assert out.strip().endswith("longest chain: not known without the run's .hydra/config.yaml")


def test_a_folder_without_stages_is_refused(stages, tmp_path, capsys):
    assert stages.main([str(tmp_path)]) == 2
    assert "no stages.json in" in capsys.readouterr().err


def test_the_longest_chain_follows_the_pipelines_order_and_bounds_the_wall_time(
    stages, tmp_path, capsys
):
    """Minutes: the flap teacher (10) then its teacher-rule finger-pull flap teacher (20), the
    named finger-pull door teacher (30) then its retrain, resumed halfway (15 for its last 500
    of 1,000 iterations: 30 whole), the door teacher (10) then a knob-door teacher from its
    actor (5), then the student (10) and its more (5). The retrain's chain is the longest:
    30 + 30 + 10 + 5 = 75; the teachers sum 105, so on 2 slots at least 105 / 2 + 15 = 67.5,
    which the chain exceeds."""
    records = [
        stage("teacher_flap", 0, 600, kind="flap"),
        stage("teacher_finger_pull_door", 0, 1800, 1000, kind="door", category="finger_pull"),
        stage("teacher_finger_pull_flap", 600, 1800, kind="flap", category="finger_pull"),
        stage("teacher_door", 1800, 2400, kind="door"),
        stage("teacher_knob_door", 2400, 2700, 200, kind="door", category="knob",
              starts_from="teacher_door"),
        stage("teacher_finger_pull_door_retrain", 9000, 9900, 1000, 500, "door", "finger_pull"),
        stage("student", 9900, 10500),
        stage("student_more", 10500, 10800, 600, 399),
    ]  # fmt: skip
    (tmp_path / "stages.json").write_text(json.dumps(records))
    (tmp_path / ".hydra").mkdir()
    (tmp_path / ".hydra" / "config.yaml").write_text(
        "pipeline:\n  own_teachers:\n    - {group: finger_pull_door, iterations: 1000}\n"
        "    - {group: knob_door, iterations: 200, from_kind: true}\n"
    )
    assert stages.main([str(tmp_path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith(
        "longest chain: teacher_finger_pull_door 30.0 → teacher_finger_pull_door_retrain ~30.0"
        " → student 10.0 → student_more 5.0 = 75.0 min."
    )
    assert "at least 75.0 on 2, 75.0 on 4 stage slots and 75.0 on any number" in last
    assert "(teachers 105.0 min summed, student 15.0)" in last


def test_a_teacher_rule_teacher_waits_for_its_kinds_teacher(stages, tmp_path, capsys):
    """Unnamed (its config names none), the finger-pull flap teacher follows the flap teacher:
    10 + 20 + the student's 10 = 40, longer than the door teacher's 25 + 10. The teachers sum
    80 minutes, so 2 slots need at least 80 / 2 + 10 = 50, 4 slots the chain's 40."""
    records = [
        stage("teacher_flap", 0, 600, kind="flap"),
        stage("teacher_door", 0, 1500, kind="door"),
        stage("teacher_drawer", 1500, 3000, kind="drawer"),
        stage("teacher_finger_pull_flap", 600, 1800, kind="flap", category="finger_pull"),
        stage("student", 3000, 3600),
    ]  # fmt: skip
    (tmp_path / "stages.json").write_text(json.dumps(records))
    (tmp_path / ".hydra").mkdir()
    (tmp_path / ".hydra" / "config.yaml").write_text("pipeline:\n  own_teachers: []\n")
    assert stages.main([str(tmp_path)]) == 0
    last = capsys.readouterr().out.strip().splitlines()[-1]
    assert last.startswith(
        "longest chain: teacher_flap 10.0 → teacher_finger_pull_flap 20.0 → student 10.0 = 40.0"
    )
    assert "at least 50.0 on 2, 40.0 on 4 stage slots and 40.0 on any number" in last
