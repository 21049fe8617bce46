"""rsl-rl log writer: every scalar to metrics.csv, optionally mirrored to wandb or TensorBoard,
and a progress bar of the launch's iterations with the training success and opening.

The CSV is what the learning-curve plots read, so runs log the same way whatever the backend,
under the tags rsl-rl and the env give (`/episode/success`, `Train/mean_reward`, ...). The
mirrors get rsl-rl's `Group/name` form (`episode/success`: a leading slash would make an empty
group). wandb runs offline unless WANDB_MODE says otherwise, so no account is needed.

wandb has one step counter per run, and it only moves forward: every iteration's scalars go in
one `log` call at step = iteration. rsl-rl's `/time` tags (a value at step = elapsed seconds)
would move that counter to seconds and make wandb drop every later iteration, so wandb gets
instead the elapsed seconds as `Perf/elapsed_seconds` at each iteration (plot any tag against it).
TensorBoard keeps a step per tag and gets every tag as it comes.
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
TIME_SUFFIX = "/time"  # rsl-rl's tags whose step is elapsed seconds, not the iteration
ELAPSED_TAG = "Perf/elapsed_seconds"  # what wandb gets of them


def mirrored_tag(tag: str) -> str:
    """`tag` as the mirrors name it: rsl-rl's `Group/name` form, no leading slash."""
    return tag.lstrip("/")


class RealIkeaLogWriter(LogWriter):
    """Writes (iteration, tag, value) rows; flushes at every iteration. With `iterations` (this
    launch's), also shows a progress bar on stderr, headed by `description` if given, on the
    terminal's `line` (0: the cursor's; processes side by side take a line each)."""

    def __init__(
        self,
        log_dir: str,
        backend: str = "none",
        project_name: str = "real-ikea",
        iterations: int | None = None,
        description: str | None = None,
        line: int = 0,
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
        self._wandb_row: dict[str, float] = {}  # the iteration's scalars, sent when it ends
        self._wandb_step = None
        self._bar = (
            tqdm(total=iterations, desc=description, unit="it", dynamic_ncols=True, position=line)
            if iterations
            else None
        )
        self._bar_values: dict[str, float] = {}
        self._bar_iteration = None  # the iteration the bar's values are of
        if backend == "wandb":
            import wandb

            os.environ.setdefault("WANDB_MODE", "offline")
            os.environ.setdefault("WANDB_DIR", str(self.log_dir))
            self._run = wandb.init(
                project=project_name, name=self.log_dir.name, dir=str(self.log_dir)
            )
        elif backend == "tensorboard":
            from torch.utils.tensorboard import SummaryWriter

            self._tb = SummaryWriter(log_dir=str(self.log_dir), flush_secs=10)

    def add_scalar(self, tag: str, scalar_value: float, global_step: int) -> None:
        if self._last_step is not None and global_step != self._last_step:
            self._file.flush()
        self._last_step = global_step
        self._csv.writerow([global_step, tag, float(scalar_value)])
        timed = tag.endswith(TIME_SUFFIX)
        if not timed:
            if self._bar_iteration is not None and global_step != self._bar_iteration:
                self._advance_bar()
            self._bar_iteration = global_step
        if tag in BAR_TAGS:
            self._bar_values[BAR_TAGS[tag]] = float(scalar_value)
        if hasattr(self, "_tb"):
            self._tb.add_scalar(mirrored_tag(tag), float(scalar_value), global_step)
        if hasattr(self, "_run"):
            self._to_wandb(tag, float(scalar_value), global_step, timed)

    def _to_wandb(self, tag: str, value: float, step: int, timed: bool) -> None:
        """Collect the iteration's scalars; send them at step = iteration once the next begins."""
        if timed:  # step is elapsed seconds: recorded as a value of the current iteration
            self._wandb_row[ELAPSED_TAG] = float(step)
            return
        if self._wandb_step is not None and step != self._wandb_step:
            self._flush_wandb()
        self._wandb_step = step
        self._wandb_row[mirrored_tag(tag)] = value

    def _flush_wandb(self) -> None:
        if self._wandb_row and self._wandb_step is not None:
            self._run.log(self._wandb_row, step=self._wandb_step)
        self._wandb_row = {}

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
            self._flush_wandb()
            self._run.finish()
        if hasattr(self, "_tb"):
            self._tb.close()
