"""Kept students read with the mirror off and on (experiments/generalist/mirror_reads.py): both
hinge sides as trained, the mirrored side reflected, kept as it comes, bad input refused before
any evaluation."""

from __future__ import annotations

import json
from types import SimpleNamespace

import pytest


@pytest.fixture
def reads(load_script, monkeypatch):
    """The script with evaluation faked: 0.7 on left-hinged doors as trained, 0.9 reflected,
    0.96 on right-hinged ones; each evaluation's (overrides, mirror) in `reads.asked`."""
    module = load_script("experiments/generalist/mirror_reads.py")
    module.asked = []

    def setup(overrides):
        return SimpleNamespace(o=overrides, task=SimpleNamespace(mirror_doors=None)), None

    def evaluate(cfg, policy, progress):
        module.asked.append((cfg.o, cfg.task.mirror_doors))
        left = "asset.hinge=left" in cfg.o
        rate = (0.9 if cfg.task.mirror_doors else 0.7) if left else 0.96
        return SimpleNamespace(summary=lambda: {"success": rate})

    monkeypatch.setattr(module, "eval_setup", setup)
    monkeypatch.setattr(module, "evaluate", evaluate)
    monkeypatch.setattr(module, "mirrored_read", lambda group: "small_left")
    return module


def kept(folder):
    (folder / ".hydra").mkdir(parents=True)
    (folder / "model_599.pt").write_bytes(b"")
    (folder / ".hydra" / "overrides.yaml").write_text("- logger=none\n- env.seed=20\n")
    return folder


def test_the_mirrored_side_is_read_as_trained_and_reflected_beside_its_twin(
    reads, tmp_path, capsys
):
    run = kept(tmp_path / "run")
    assert reads.main([str(run)]) == 0
    assert [mirror for _, mirror in reads.asked] == [False, False, True]
    assert "asset.hinge=left" in reads.asked[2][0]
    row = capsys.readouterr().out.strip().splitlines()[-1]
    assert "| two_point_door | left | 0.70 [0.56, 0.81] | 0.90 [0.79, 0.96] | 0.96" in row
    assert "| +0.20 [" in row and "| -0.06 [" in row  # reflected - as trained; - the twin side
    kept_reads = json.loads((run / "mirror_reads.json").read_text())["two_point_door"]
    assert kept_reads == {"small_left": {"off": 0.7, "on": 0.9}, "small_right": {"off": 0.96}}
    reads.asked.clear()  # a second reading evaluates nothing again
    assert reads.main([str(run)]) == 0 and reads.asked == []


def test_a_folder_without_a_student_is_refused_before_any_evaluation(reads, tmp_path, capsys):
    good = kept(tmp_path / "good")
    assert reads.main([str(good), str(tmp_path / "missing")]) == 2
    assert "missing" in capsys.readouterr().err and reads.asked == []
