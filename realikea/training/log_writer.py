"""rsl-rl log writer: every scalar to metrics.csv, optionally mirrored to wandb or TensorBoard,
and a progress bar of the launch's iterations with the training success and opening.

The CSV is what the learning-curve plots read, so runs log the same way whatever the backend.
wandb runs offline unless WANDB_MODE says otherwise, so no account is needed.
"""

from __future__ import annotations

import csv
import os
from pathlib import Path

from rsl_rl.utils.log_writer import LogWriter
from tqdm import tqdm

BACKENDS = ("none", "wandb", "tensorboard")
# tag -> the bar's label: what a run is doing, at a glance
BAR_TAGS = {
    "/episode/success": "success",
    "/episode/opening": "opening",
    "Train/mean_reward": "reward",
}


class RealIkeaLogWriter(LogWriter):
    """Writes (iteration, tag, value) rows; flushes at every iteration. With `iterations` (this
    launch's), also shows a progress bar on stderr."""

    def __init__(
        self,
        log_dir: str,
        backend: str = "none",
        project_name: str = "real-ikea",
        iterations: int | None = None,
    ):
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
        self._bar = tqdm(total=iterations, unit="it", dynamic_ncols=True) if iterations else None
        self._bar_values: dict[str, float] = {}
        self._bar_iteration = None  # the iteration the bar's values are of
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
        if not tag.endswith("/time"):  # rsl-rl's `/time` tags count seconds, not iterations
            if self._bar_iteration is not None and global_step != self._bar_iteration:
                self._advance_bar()
            self._bar_iteration = global_step
        if tag in BAR_TAGS:
            self._bar_values[BAR_TAGS[tag]] = float(scalar_value)
        if self._mirror is not None:
            self._mirror(tag, float(scalar_value), global_step)

    def store_config(self, env_cfg, train_cfg: dict) -> None:
        if hasattr(self, "_run"):
            self._run.config.update({"train": train_cfg}, allow_val_change=True)

    def _advance_bar(self) -> None:
        if self._bar is not None and self._bar_iteration is not None:
            self._bar.set_postfix(
                {k: f"{v:.2f}" for k, v in self._bar_values.items()}, refresh=False
            )
            self._bar.update(1)

    def stop(self) -> None:
        self._advance_bar()  # the last iteration
        if self._bar is not None:
            self._bar.close()
        self._file.close()
        if hasattr(self, "_run"):
            self._run.finish()
        if hasattr(self, "_tb"):
            self._tb.close()
