"""rsl-rl log writer: every scalar to metrics.csv, optionally mirrored to wandb or TensorBoard.

The CSV is what the learning-curve plots read, so runs log the same way whatever the backend.
wandb runs offline unless WANDB_MODE says otherwise, so no account is needed.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

from rsl_rl.utils.log_writer import LogWriter

BACKENDS = ("none", "wandb", "tensorboard")


class RealIkeaLogWriter(LogWriter):
    """Writes (iteration, tag, value) rows; flushes at every iteration."""

    def __init__(self, log_dir: str, backend: str = "none", project_name: str = "real-ikea"):
        if backend not in BACKENDS:
            raise ValueError(f"logger backend {backend!r}: use one of {', '.join(BACKENDS)}")
        self.log_dir = Path(log_dir)
        self.log_dir.mkdir(parents=True, exist_ok=True)
        self._file = (self.log_dir / "metrics.csv").open("a", newline="")
        self._csv = csv.writer(self._file)
        if self._file.tell() == 0:
            self._csv.writerow(["iteration", "tag", "value"])
        self._last_step = None
        self._mirror = None
        if backend == "wandb":
            import wandb

            os.environ.setdefault("WANDB_MODE", "offline")
            os.environ.setdefault("WANDB_DIR", str(self.log_dir))
            self._run = wandb.init(
                project=project_name, name=self.log_dir.name, dir=str(self.log_dir)
            )
            self._mirror = lambda tag, value, step: self._run.log({tag: value}, step=step)
        elif backend == "tensorboard":
            from torch.utils.tensorboard import SummaryWriter

            writer = SummaryWriter(log_dir=str(self.log_dir), flush_secs=10)
            self._mirror = writer.add_scalar
            self._tb = writer

    def add_scalar(self, tag: str, scalar_value: float, global_step: int) -> None:
        if self._last_step is not None and global_step != self._last_step:
            self._file.flush()
        self._last_step = global_step
        self._csv.writerow([global_step, tag, float(scalar_value)])
        if self._mirror is not None:
            self._mirror(tag, float(scalar_value), global_step)

    def store_config(self, env_cfg, train_cfg: dict) -> None:
        if hasattr(self, "_run"):
            self._run.config.update({"train": train_cfg}, allow_val_change=True)

    def stop(self) -> None:
        self._file.close()
        if hasattr(self, "_run"):
            self._run.finish()
        if hasattr(self, "_tb"):
            self._tb.close()
