"""Training logs: every scalar in metrics.csv, wandb offline without an account, a progress bar
of the iterations."""

from __future__ import annotations

import csv
import struct
import time
import zlib

import pytest
import torch

from realikea.errors import RealIkeaError
from realikea.training.log_writer import RealIkeaLogWriter
from realikea.training.wandb_file import run_file, wandb_history, wandb_records


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


def closed_run_file(run_dir, timeout: float = 120.0):
    """The run's `.wandb` file once wandb's writer process has closed it (its `exit` record is
    in): `finish()` returns before that process has flushed on a loaded machine."""
    deadline = time.monotonic() + timeout
    while True:
        path = run_file(run_dir)
        kinds = {r.WhichOneof("record_type") for r in wandb_records(path)}
        if "exit" in kinds or time.monotonic() > deadline:
            return path
        time.sleep(0.5)


def test_wandb_keeps_every_iteration_of_a_run_whose_iterations_take_seconds(tmp_path, monkeypatch):
    """rsl-rl's own logger, iterations of 2 s: wandb holds the reward and the success of every
    iteration at steps 0 ... N-1 (its `/time` tags, stepped in seconds, used to move wandb's
    step past the iterations and drop them)."""
    from rsl_rl.utils.logger import Logger

    monkeypatch.setenv("WANDB_MODE", "offline")
    monkeypatch.setenv("WANDB_SILENT", "true")
    iterations, num_envs = 6, 2
    cfg = {
        "num_steps_per_env": 1,
        "algorithm": {},
        "logger": {
            "class_name": "realikea.training.log_writer:RealIkeaLogWriter",
            "backend": "wandb",
        },
    }
    logger = Logger(str(tmp_path), cfg, {}, num_envs, False, 1, 0, "cpu")
    logger.init_logging_writer()
    for it in range(iterations):
        extras = {"log": {"/episode/success": torch.tensor([0.1 * it, 0.1 * it])}}
        logger.process_env_step(torch.full((num_envs,), float(it)), torch.ones(num_envs), extras)
        logger.log(it, 0, iterations, 1.5, 0.5, {"surrogate": 0.0}, 1e-3, torch.ones(4), None)
    logger.stop_logging_writer()

    history = wandb_history(closed_run_file(tmp_path))
    steps = list(range(iterations))
    assert history["Train/mean_reward"] == {it: it / 2 for it in steps}  # mean of 0..it
    assert history["episode/success"] == pytest.approx({it: 0.1 * it for it in steps})
    assert history["Perf/elapsed_seconds"] == {it: 2.0 * (it + 1) for it in steps}
    assert not [tag for tag in history if tag.startswith("/")]  # rsl-rl's Group/name form
    assert _rows(tmp_path)[0][1] == "/episode/success"  # metrics.csv keeps its names


def _history_file(path, steps):
    """A `.wandb` file of one FULL chunk per history row {"x": step}, as wandb lays it out."""
    from wandb.proto import wandb_internal_pb2

    data = bytearray(struct.pack("<4sHB", b":W&B", 0xBEE1, 0))
    for step in steps:
        record = wandb_internal_pb2.Record()
        record.history.step.num = step
        record.history.item.add(key="x", value_json=str(step))
        body = record.SerializeToString()
        crc = zlib.crc32(body, zlib.crc32(bytes([1])))
        data += struct.pack("<IHB", crc, len(body), 1) + body
    path.write_bytes(bytes(data))
    return bytes(data)


def test_a_file_still_being_written_is_read_up_to_its_last_whole_record(tmp_path):
    path = tmp_path / "run-x.wandb"
    data = _history_file(path, range(3))
    assert wandb_history(path) == {"x": {0: 0, 1: 1, 2: 2}}
    path.write_bytes(data[:-3])  # the last record's bytes not all flushed yet
    assert wandb_history(path) == {"x": {0: 0, 1: 1}}


def test_a_corrupt_chunk_is_refused_by_its_offset(tmp_path):
    path = tmp_path / "run-x.wandb"
    data = bytearray(_history_file(path, range(3)))
    data[-1] ^= 0xFF
    path.write_bytes(bytes(data))
    with pytest.raises(RealIkeaError, match=r"run-x.wandb: the chunk at byte \d+ fails its crc32"):
        wandb_records(path)


def test_a_file_that_is_not_a_wandb_run_is_refused_by_name(tmp_path):
    path = tmp_path / "run-x.wandb"
    path.write_bytes(b"not a wandb log")
    with pytest.raises(RealIkeaError, match="run-x.wandb is not a wandb run file"):
        wandb_records(path)
