"""The Hydra entry point of training, shared by `python train.py ...` and `realikea train ...`:
train PPO on the opening task (or a pipeline of stages: realikea/training/pipeline.py) in the
run's Hydra directory, then optionally evaluate it."""

from __future__ import annotations

import time

import hydra
from hydra.core.hydra_config import HydraConfig
from omegaconf import DictConfig

from realikea.eval.runs import check_eval_spec, evaluate_run
from realikea.files import CONF_DIR
from realikea.rewards import store_configs
from realikea.training.pipeline import pipelined, train_pipeline
from realikea.training.preflight import user_errors
from realikea.training.train import train

store_configs()  # task/reward=<variant>, before Hydra composes


@hydra.main(config_path=str(CONF_DIR), config_name="config", version_base="1.3")
def main(cfg: DictConfig) -> None:
    """Train in this run's Hydra directory (config, checkpoints, metrics.csv, logs), then
    optionally evaluate the last checkpoint (`train.eval_after`: eval.json). A bad input stops it
    with one line naming it (`user_errors`)."""
    with user_errors():
        _train_and_evaluate(cfg)


def _train_and_evaluate(cfg: DictConfig) -> None:
    hydra_cfg = HydraConfig.get()
    overrides = list(hydra_cfg.overrides.task)
    if cfg.train.get("eval_after"):
        check_eval_spec(cfg.train.eval_after, overrides)  # fail now, not after training
    begin = time.perf_counter()
    run_dir = hydra_cfg.runtime.output_dir
    staged = pipelined(cfg)
    checkpoint = train_pipeline(cfg, run_dir, overrides) if staged else train(cfg, run_dir)
    print(f"final checkpoint: {checkpoint}")
    if cfg.train.get("eval_after"):
        seconds = time.perf_counter() - begin
        evaluate_run(
            cfg.train.eval_after, hydra_cfg.runtime.output_dir, checkpoint, overrides, seconds
        )
