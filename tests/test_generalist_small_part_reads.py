"""Kept runs' students on the small-part reads (experiments/generalist/small_part_reads.py): a
door on each hinge side apart, the run's own launch carried, kept as it comes, and bad input
refused before any evaluation."""

from __future__ import annotations

import json
from types import SimpleNamespace

import pytest

import realikea.training.validation as validation


@pytest.fixture
def reads(load_script, monkeypatch):
    """The script with evaluation faked: 0.7 on the left-hinged doors, 0.96 elsewhere; the
    overrides of each evaluation in `reads.asked`."""
    module = load_script("experiments/generalist/small_part_reads.py")
    module.asked = []

    def setup(overrides):
        module.asked.append(overrides)
        return SimpleNamespace(o=overrides), None

    def evaluate(cfg, policy, progress):
        rate = 0.7 if "asset.hinge=left" in cfg.o else 0.96
        return SimpleNamespace(summary=lambda: {"success": rate})

    monkeypatch.setattr(validation, "eval_setup", setup)
    monkeypatch.setattr(validation, "evaluate", evaluate)
    return module


def kept(folder, overrides=("logger=none", "collision=hull", "env.seed=20")):
    (folder / ".hydra").mkdir(parents=True)
    (folder / "model_399.pt").write_bytes(b"")
    (folder / ".hydra" / "overrides.yaml").write_text("".join(f"- {o}\n" for o in overrides))
    return folder


def test_a_door_is_read_on_each_side_with_the_runs_launch_then_kept(reads, tmp_path, capsys):
    run = kept(tmp_path / "run")
    assert reads.main([str(run), "--groups", "two_point_door", "two_point_drawer"]) == 0
    out = capsys.readouterr().out
    assert "| two_point_door | small_left | 0.70 [0.56, 0.81] |" in out
    assert "| two_point_door | small_right | 0.96 [0.87, 0.99] |" in out
    assert "| two_point_drawer | small | 0.96 [0.87, 0.99] |" in out
    assert len(reads.asked) == 3
    left = reads.asked[0]
    assert {"collision=hull", "asset.split=train", "env.seed=2000", "episodes=50"} <= set(left)
    assert "asset.hinge=left" in left and any(o.startswith("asset.withhold=[") for o in left)
    assert not any(o.startswith("asset.hinge") for o in reads.asked[2])  # a drawer: no side
    kept_reads = json.loads((run / "small_part_reads.json").read_text())
    assert kept_reads["two_point_door"] == {"small_left": 0.7, "small_right": 0.96}
    reads.asked.clear()  # a second reading evaluates nothing again
    assert reads.main([str(run), "--groups", "two_point_door"]) == 0 and reads.asked == []


def test_a_run_without_its_launch_is_refused_before_any_evaluation(reads, tmp_path, capsys):
    good = kept(tmp_path / "good")
    bare = tmp_path / "bare"
    bare.mkdir()
    (bare / "model_399.pt").write_bytes(b"")
    assert reads.main([str(good), str(bare)]) == 2
    assert "bare: no .hydra/overrides.yaml" in capsys.readouterr().err and reads.asked == []
