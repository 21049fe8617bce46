"""Training logs: every scalar in metrics.csv, wandb offline without an account, a progress bar
of the iterations."""

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


def test_the_progress_bar_counts_iterations_not_the_seconds_of_time_tags(tmp_path, capsys):
    writer = RealIkeaLogWriter(str(tmp_path), backend="none", iterations=3)
    for it in range(3):
        writer.add_scalar("/episode/success", 0.25 * it, it)
        writer.add_scalar("Train/mean_reward", 1.0, it)
        writer.add_scalar("Train/mean_reward/time", 1.0, 17 * it + 5)  # seconds, not iterations
    assert writer._bar.n == 2  # the last iteration counts once it is complete
    writer.stop()
    assert writer._bar.n == 3
    bar = capsys.readouterr().err
    assert "3/3" in bar and "success=0.50" in bar and "reward=1.00" in bar
