"""Hydra entry point: train PPO on the opening task.

python train.py collision=hull resistance=high
python train.py -m collision=coacd,hull resistance=smooth,normal,high
python train.py -m hydra/launcher=joblib collision=coacd,hull   # runs in parallel locally
python train.py -m +experiment=fidelity_ablation   # the ablation (realikea/conf/experiment/)
"""

import time

import hydra
from hydra.core.hydra_config import HydraConfig
from omegaconf import DictConfig


@hydra.main(config_path="realikea/conf", config_name="config", version_base="1.3")
def main(cfg: DictConfig) -> None:
    """Train in this run's Hydra directory (config, checkpoints, metrics.csv, logs), then
    optionally evaluate the last checkpoint (`train.eval_after`: eval.json)."""
    from realikea.training.train import train

    hydra_cfg = HydraConfig.get()
    begin = time.perf_counter()
    checkpoint = train(cfg, hydra_cfg.runtime.output_dir)
    print(f"final checkpoint: {checkpoint}")
    if cfg.train.get("eval_after"):
        from realikea.eval.runs import evaluate_run

        seconds = time.perf_counter() - begin
        overrides = list(hydra_cfg.overrides.task)
        evaluate_run(
            cfg.train.eval_after, hydra_cfg.runtime.output_dir, checkpoint, overrides, seconds
        )


if __name__ == "__main__":
    main()
