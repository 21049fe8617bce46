"""Checks a training launch passes before Hydra writes its folder: its inputs (`check_inputs`:
settings in range, a resumable checkpoint, a non-empty draw, ...), and a folder that holds no
other run (two launches never mix their metrics and checkpoints)."""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator
from pathlib import Path

from hydra.experimental.callback import Callback
from omegaconf import DictConfig, OmegaConf

from realikea.errors import RealIkeaError
from realikea.eval.sweep import checkpoints
from realikea.training.pipeline import check_launch, check_pipeline, pipelined
from realikea.training.train import check_inputs

RUN_MARKS = ("metrics.csv", "model_*.pt")  # files a launch leaves in its folder
FULL_TRACE = "HYDRA_FULL_ERROR"  # =1: a user error shows its traceback, as Hydra's own errors do


def held_runs(folder: Path) -> list[Path]:
    """The run folders at or under `folder` that hold a launch's files."""
    found = {p.parent for mark in RUN_MARKS for p in Path(folder).rglob(mark)}
    return sorted(found)


def check_fresh_folder(folder: Path, resume) -> None:
    """Refuse a launch into a folder that already holds a run, unless it resumes one
    (`train.resume=`), naming how to continue it and how to start afresh."""
    if resume:
        return
    held = held_runs(folder)
    if not held:
        return
    run = held[0]
    found = checkpoints(run) if any(run.glob("model_*.pt")) else []
    resume_hint = f"train.resume={found[-1][1]} to continue it, or " if found else ""
    raise RealIkeaError(
        f"{run} already holds a run (its metrics.csv or checkpoints): use {resume_hint}"
        f"a fresh folder (hydra.run.dir={Path(folder)}_2, or none for a dated one)"
    )


@contextlib.contextmanager
def user_errors(prog: str = "train") -> Iterator[None]:
    """A `RealIkeaError` as one line on stderr and exit status 2; its traceback with
    HYDRA_FULL_ERROR=1."""
    try:
        yield
    except RealIkeaError as err:
        if os.environ.get(FULL_TRACE) == "1":
            raise
        print(f"{prog}: error: {err}", file=sys.stderr)
        sys.exit(2)


class Preflight(Callback):
    """Hydra callback (config.yaml's `hydra.callbacks`): the checks, before the run's or the
    sweep's folder is written."""

    def on_run_start(self, config: DictConfig, **kwargs) -> None:
        with user_errors():
            if pipelined(config):
                check_launch(config, list(config.hydra.overrides.task))
            else:
                check_inputs(config)
            check_fresh_folder(Path(OmegaConf.select(config, "hydra.run.dir")), config.train.resume)

    def on_multirun_start(self, config: DictConfig, **kwargs) -> None:
        with user_errors():  # a pipeline's stages are checked per job, when it starts
            check_pipeline(config) if pipelined(config) else check_inputs(config)
            check_fresh_folder(
                Path(OmegaConf.select(config, "hydra.sweep.dir")), config.train.resume
            )
