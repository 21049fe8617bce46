"""The screen's validation rule (experiments/generalist/validation_rule.py): every group of each
run's student on the validation draw in smooth and high, resumable, and the verdict."""

from __future__ import annotations

import json
from types import SimpleNamespace

import pytest
from omegaconf import OmegaConf

import realikea.eval.library_grid as library_grid
from realikea.assets.catalog import GROUPS


@pytest.fixture
def rule(load_script, monkeypatch):
    """The script with evaluation faked: 0.9 everywhere but two-point doors in high (0.6) on a
    run named `short`; the overrides of each evaluation in `rule.asked`."""
    module = load_script("experiments/generalist/validation_rule.py")
    module.asked = []

    def setup(overrides):
        module.asked.append(overrides)
        return OmegaConf.create({"collision": {"source": "coacd"}, "scene": {"name": "kitchen"},
                                 "asset": {"split": "train"}, "o": overrides}), None  # fmt: skip

    def evaluate(cfg, policy, progress):
        overrides = list(cfg.o)
        short = "short" in overrides[1] and "asset=two_point" in overrides
        rate = (
            0.6
            if short and "asset.kind=door" in overrides and "resistance=high" in overrides
            else 0.9
        )
        summary = {"episodes": 50, "success": rate, "partial": 0.0, "fail": 1 - rate}
        return SimpleNamespace(summary=lambda: summary, episodes=[])

    monkeypatch.setattr(library_grid, "eval_setup", setup)
    monkeypatch.setattr(library_grid, "evaluate", evaluate)
    monkeypatch.setattr(
        module, "run_config", lambda c: OmegaConf.create({"collision": {"source": "coacd"}})
    )
    return module


def kept(folder):
    folder.mkdir(parents=True)
    (folder / "model_399.pt").write_bytes(b"")
    return folder


def test_every_group_in_both_modes_on_the_validation_draw_then_the_verdict(rule, tmp_path, capsys):
    good, short = kept(tmp_path / "good"), kept(tmp_path / "short")
    assert rule.main([str(good), str(short)]) == 0
    out = capsys.readouterr().out
    assert "adopted: no (1 of 2 runs pass: smooth >= 0.8, high >= 0.7)" in out
    assert "| two_point_door | 0.90 [0.79, 0.96] | 0.60 [0.46, 0.72] ✗ |" in out
    assert len(rule.asked) == 2 * len(GROUPS) * 2
    first = rule.asked[0]
    assert {"asset.split=train", "env.seed=2000", "episodes=50", "collision=coacd"} <= set(first)
    lines = (good / "validation_cells.jsonl").read_text().splitlines()
    assert len(lines) == 18 and json.loads(lines[0])["command"].startswith("realikea eval ")
    rule.asked.clear()  # a second reading evaluates nothing again
    assert rule.main([str(good)]) == 0 and rule.asked == []
    assert "adopted: yes (1 of 1 runs pass" in capsys.readouterr().out


def test_a_folder_without_a_checkpoint_is_refused_before_any_evaluation(rule, tmp_path, capsys):
    good = kept(tmp_path / "good")
    assert rule.main([str(good), str(tmp_path / "empty")]) == 2
    assert "empty: no kept run with a model_*.pt" in capsys.readouterr().err and rule.asked == []
