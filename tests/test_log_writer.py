"""Training logs: every scalar in metrics.csv, wandb offline without an account."""

from __future__ import annotations

import csv

import pytest

from realikea.training.log_writer import RealIkeaLogWriter


def _rows(path):
    with (path / "metrics.csv").open() as f:
        return [(int(r["iteration"]), r["tag"], float(r["value"])) for r in csv.DictReader(f)]


def test_csv_backend(tmp_path):
    writer = RealIkeaLogWriter(str(tmp_path), backend="none")
    writer.add_scalar("Train/mean_reward", 1.5, 0)
    writer.add_scalar("/episode/success", 0.25, 1)
    writer.stop()
    assert _rows(tmp_path) == [(0, "Train/mean_reward", 1.5), (1, "/episode/success", 0.25)]


def test_wandb_backend_runs_offline(tmp_path, monkeypatch):
    monkeypatch.delenv("WANDB_MODE", raising=False)
    monkeypatch.setenv("WANDB_SILENT", "true")
    writer = RealIkeaLogWriter(str(tmp_path), backend="wandb")
    writer.add_scalar("Train/mean_reward", 2.0, 0)
    writer.stop()
    assert _rows(tmp_path) == [(0, "Train/mean_reward", 2.0)]
    assert list((tmp_path / "wandb").glob("offline-run-*"))


def test_unknown_backend(tmp_path):
    with pytest.raises(ValueError, match="logger backend 'mlflow'"):
        RealIkeaLogWriter(str(tmp_path), backend="mlflow")
