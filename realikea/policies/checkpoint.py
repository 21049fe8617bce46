"""A trained rsl-rl actor loaded from a checkpoint of a Real-IKEA run, acting deterministically."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from rsl_rl.models import MLPModel
from tensordict import TensorDict

from realikea.errors import RealIkeaError
from realikea.files import repo_path
from realikea.tasks import observations
from realikea.tasks.open_task import ACTION_SIZE

LAYOUT_FILE = "observation_layout.json"  # a run's observation layout, beside its checkpoints


def check_layout(checkpoint: Path) -> None:
    """Refuse a checkpoint trained on another observation layout."""
    layout_file = Path(checkpoint).parent / LAYOUT_FILE
    if not layout_file.is_file():
        raise RealIkeaError(f"{checkpoint}: no {LAYOUT_FILE} beside it; not a Real-IKEA run")
    stored = [tuple(item) for item in json.loads(layout_file.read_text())]
    if stored != list(observations.LAYOUT):
        raise RealIkeaError(
            f"{checkpoint}: trained on observation layout {stored}, this code uses "
            f"{list(observations.LAYOUT)}"
        )


def run_config(checkpoint: Path) -> DictConfig:
    """The training config of the run a checkpoint belongs to (Hydra's .hydra/config.yaml)."""
    path = Path(checkpoint).parent / ".hydra" / "config.yaml"
    if not path.is_file():
        raise RealIkeaError(f"{checkpoint}: no training config at {path}")
    return OmegaConf.load(path)


class CheckpointPolicy:
    """The actor MLP of a checkpoint; `act` maps observations (N, 28) to actions (N, 5)."""

    name = "checkpoint"

    def __init__(self, path: Path):
        path = Path(path)
        if not path.is_file():
            raise RealIkeaError(f"checkpoint not found: {path}")
        check_layout(path)
        self.run_cfg = run_config(path)
        agent = self.run_cfg.agent
        try:
            state = torch.load(path, map_location="cpu", weights_only=False)["actor_state_dict"]
        except Exception as err:  # truncated zip, pickle of something else, missing key
            raise RealIkeaError(f"{path}: not a readable rsl-rl checkpoint ({err})") from err
        dummy = TensorDict({"policy": torch.zeros(1, observations.SIZE)}, batch_size=[1])
        self.actor = MLPModel(
            dummy,
            {"actor": ["policy"]},
            "actor",
            ACTION_SIZE,
            hidden_dims=list(agent.actor_hidden_dims),
            activation=str(agent.activation),
            obs_normalization=bool(agent.empirical_normalization),
            distribution_cfg={"class_name": "GaussianDistribution", "init_std": 1.0},
        )
        try:
            self.actor.load_state_dict(state)
        except RuntimeError as err:
            raise RealIkeaError(f"{path}: actor does not match the run's network ({err})") from err
        self.actor.eval()

    @classmethod
    def from_config(cls, cfg: DictConfig) -> CheckpointPolicy:
        """`policy.path` names the checkpoint (relative paths from the repository root)."""
        if not cfg.policy.path:
            raise RealIkeaError("policy=checkpoint needs policy.path=PATH/model_<it>.pt")
        return cls(repo_path(cfg.policy.path))

    def reset(self, env_ids, facts) -> None:
        """Stateless: nothing to forget between episodes (and no privileged scene facts)."""

    @torch.inference_mode()
    def act(self, obs: np.ndarray) -> np.ndarray:
        batch = torch.as_tensor(obs, dtype=torch.float32)
        td = TensorDict({"policy": batch}, batch_size=[batch.shape[0]])
        return self.actor(td).numpy().astype(np.float64)
