"""Hydra entry point: train PPO on the opening task.

python train.py collision=hull resistance=high
python train.py -m collision=coacd,hull resistance=smooth,normal,high
python train.py -m hydra/launcher=joblib collision=coacd,hull   # runs in parallel locally
"""

import hydra
from hydra.core.hydra_config import HydraConfig
from omegaconf import DictConfig


@hydra.main(config_path="conf", config_name="config", version_base="1.3")
def main(cfg: DictConfig) -> None:
    """Train in this run's Hydra directory (config, checkpoints, metrics.csv, logs)."""
    from realikea.training.train import train

    checkpoint = train(cfg, HydraConfig.get().runtime.output_dir)
    print(f"final checkpoint: {checkpoint}")


if __name__ == "__main__":
    main()
