"""The generalist aims' driver (experiments/generalist/aims.py): which commands it trains, where
it keeps them and which cells it evaluates each kept run on (no training)."""

from __future__ import annotations

import sys

import pytest


@pytest.fixture
def aims(load_script):
    return load_script("experiments/generalist/aims.py")


def test_each_recipe_trains_its_command_on_its_own_seeds_as_long_as_its_config_says(aims, capsys):
    assert aims.main(["--dry-run"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split("env.seed=")[1].split()[0] for line in lines] == [
        "200", "201", "202", "210", "211", "212"
    ]  # fmt: skip
    assert all("collision=hull resistance=high" in line for line in lines[3:])
    assert not any("collision=" in line for line in lines[:3])
    run = aims.aim_run("hull_high", 210)
    cfg = aims.load_config(run.overrides)
    assert run.staged and cfg.pipeline.name != "none"  # python train.py trains in stages ...
    more = cfg.pipeline.student_more  # ... its student last, trained on past its iterations
    assert run.iterations == cfg.pipeline.student.iterations + more.iterations == 600
    assert aims.kept_dir(run) == aims.RESULTS / "hull_high" / "s210"


def test_a_kept_run_is_evaluated_on_its_recipes_cells(aims, monkeypatch, tmp_path):
    monkeypatch.setattr(sys.modules[aims.kept_dir.__module__], "RESULTS", tmp_path)
    (tmp_path / "hull_high/s210").mkdir(parents=True)
    (tmp_path / "hull_high/s210/model_1499.pt").write_bytes(b"")
    monkeypatch.setattr(aims, "WORKSPACE", tmp_path)
    calls = []
    monkeypatch.setattr(
        aims, "evaluate_grid", lambda ckpt, cells, modes, extra: calls.append((cells, modes, extra))
    )
    aims.evaluate(aims.QueuedRun("hull_high_s210", (), 1500))
    assert calls == [
        (tmp_path / "hull_high/s210_own/cells.jsonl", ("high",), ["collision=hull"]),
        (tmp_path / "hull_high/s210/cells.jsonl", ("high",), []),
    ]


def test_bad_seeds_are_refused_before_any_work(aims, capsys):
    with pytest.raises(SystemExit):
        aims.main(["--seeds", "-1"])
    assert "seeds must be >= 0" in capsys.readouterr().err


def test_a_kept_runs_frames_are_recorded_once_every_group_has_some(aims, monkeypatch, tmp_path):
    monkeypatch.setattr(sys.modules[aims.kept_dir.__module__], "RESULTS", tmp_path)
    monkeypatch.setattr(aims, "RESULTS", tmp_path)
    monkeypatch.setattr(aims, "WORKSPACE", tmp_path)
    calls = []
    monkeypatch.setattr(aims.subprocess, "run", lambda command, check: calls.append(command))
    run = aims.QueuedRun("hull_high_s210", (), 1500)
    frames = tmp_path / "hull_high/s210/frames"
    frames.mkdir(parents=True)
    (frames / "door_knob_success_pinch.png").write_bytes(b"")  # one group of nine: a stopped call
    aims.record_frames(run)
    assert len(calls) == 1
    assert calls[0][2:] == ["hull_high/s210", "drawer door flap", "4", "outcome", "collision=hull"]
    for kind in aims.KINDS:
        for category in aims.CATEGORIES:
            (frames / f"{kind}_{category}_fail_none.png").write_bytes(b"")
    aims.record_frames(run)
    assert len(calls) == 1
