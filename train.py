"""Hydra entry point for training; until the learning stack lands it composes and prints the config.

    python train.py collision=hull resistance=high
    python train.py -m collision=coacd,hull resistance=smooth,normal,high
"""

import hydra
from omegaconf import DictConfig, OmegaConf


@hydra.main(config_path="conf", config_name="config", version_base="1.3")
def main(cfg: DictConfig) -> None:
    """Print the resolved configuration of this run."""
    print(OmegaConf.to_yaml(cfg, resolve=True))


if __name__ == "__main__":
    main()
