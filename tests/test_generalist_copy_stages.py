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
