"""Copying kept stages into a pipeline's work folder (experiments/generalist/copy_stages.py):
folders and stages.json records, a later source's record winning, bad input refused first."""

from __future__ import annotations

import json

import pytest


@pytest.fixture
def copy_stages(load_script):
    return load_script("experiments/generalist/copy_stages.py")


def kept_run(folder, stages: dict[str, float]):
    """A kept run with a stage folder and record per stage (its success) and a student."""
    for name in stages:
        (folder / name).mkdir(parents=True)
        (folder / name / "model_399.pt").write_text(name)
    records = [{"name": n, "success": {"g": v}} for n, v in stages.items()]
    (folder / "stages.json").write_text(json.dumps([*records, {"name": "student"}]))
    return folder


def test_stages_of_several_runs_are_copied_with_their_records(copy_stages, tmp_path):
    first = kept_run(tmp_path / "r15", {"teacher_door": 0.9, "teacher_knob_door": 0.2})
    later = kept_run(tmp_path / "r19", {"teacher_knob_door": 0.95, "teacher_flap": 0.5})
    work = tmp_path / "work"
    assert copy_stages.main([str(work), str(first), f"{later}:teacher_knob_door"]) == 0
    assert sorted(p.name for p in work.iterdir()) == [
        "stages.json", "teacher_door", "teacher_knob_door"
    ]  # fmt: skip
    assert (work / "teacher_knob_door/model_399.pt").read_text() == "teacher_knob_door"
    merged = {s["name"]: s["success"]["g"] for s in json.loads((work / "stages.json").read_text())}
    assert merged == {"teacher_door": 0.9, "teacher_knob_door": 0.95}  # no student


@pytest.mark.parametrize("source, message", [
    ("r15:teacher_flap", "r15:teacher_flap: no stage folder teacher_flap"),
    ("nowhere", "nowhere: no such run folder"),
])  # fmt: skip
def test_a_missing_source_or_stage_is_refused_before_anything_is_copied(
    copy_stages, tmp_path, monkeypatch, capsys, source, message
):
    monkeypatch.chdir(tmp_path)
    kept_run(tmp_path / "r15", {"teacher_door": 0.9})
    assert copy_stages.main(["work", "r15", source]) == 2
    assert message in capsys.readouterr().err and not (tmp_path / "work").exists()


def test_a_later_launchs_records_of_the_copied_stages_win(copy_stages, tmp_path):
    first = kept_run(tmp_path / "r24", {"teacher_door": 0.9, "teacher_flap": 0.5})
    later = kept_run(tmp_path / "r25", {"teacher_two_point_flap_fine_tuned": 1.0})
    records = json.loads((later / "stages.json").read_text())
    records.append({"name": "teacher_door", "success": {"g": 0.9}, "validation_high": 0.8})
    (later / "stages.json").write_text(json.dumps(records))
    work = tmp_path / "work"
    assert copy_stages.main([str(work), str(first), str(later), "--records-from", str(later)]) == 0
    merged = {s["name"]: s for s in json.loads((work / "stages.json").read_text())}
    assert merged["teacher_door"]["validation_high"] == 0.8  # read again by the later launch
    assert merged["teacher_flap"]["success"] == {"g": 0.5}  # the later launch has no record
    assert sorted(merged) == ["teacher_door", "teacher_flap", "teacher_two_point_flap_fine_tuned"]


def test_records_from_a_run_without_them_are_refused_before_anything_is_copied(
    copy_stages, tmp_path, capsys
):
    first = kept_run(tmp_path / "r24", {"teacher_door": 0.9})
    work = tmp_path / "work"
    assert copy_stages.main([str(work), str(first), "--records-from", str(tmp_path)]) == 2
    assert "no stages.json there" in capsys.readouterr().err and not work.exists()
