"""A trained rsl-rl actor loaded from a checkpoint of a Real-IKEA run, acting on its mean action
(or, `policy.sample`, on samples of its Gaussian, as it acted in training)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from rsl_rl.models import MLPModel
from tensordict import TensorDict

from realikea.errors import RealIkeaError
from realikea.files import atomic_path, repo_path
from realikea.tasks import observations
from realikea.tasks.open_task import ACTION_SIZE

# beside the checkpoints of runs made before checkpoints carried their layout and config
LAYOUT_FILE = "observation_layout.json"


def checkpoint_infos(cfg: DictConfig) -> dict:
    """What a checkpoint carries besides the weights (rsl-rl's `save(path, infos)`): the
    observation layout it was trained on and the run's resolved config, so it evaluates alone."""
    return {
        "observation_layout": [list(item) for item in observations.LAYOUT],
        "config": OmegaConf.to_container(cfg, resolve=True),
    }


def load_saved(checkpoint: Path) -> dict:
    """The checkpoint's saved dict, with clear errors for a missing or unreadable file."""
    path = Path(checkpoint)
    if not path.is_file():
        raise RealIkeaError(f"checkpoint not found: {path}")
    try:
        saved = torch.load(path, map_location="cpu", weights_only=False)
    except Exception as err:  # truncated zip, pickle of something else
        raise RealIkeaError(f"{path}: not a readable rsl-rl checkpoint ({err})") from err
    if not isinstance(saved, dict) or "actor_state_dict" not in saved:
        raise RealIkeaError(f"{path}: not a readable rsl-rl checkpoint (no actor_state_dict)")
    return saved


# what evaluation reads of a checkpoint: the actor (its normaliser included) and what it carries
EVALUATION_KEYS = ("actor_state_dict", "iter", "infos")


def slim_checkpoint(source: Path, target: Path) -> Path:
    """Write the part of a checkpoint evaluation needs (`EVALUATION_KEYS`: no critic, no
    optimiser state), carrying its layout and config even if an older run kept them beside it,
    to `target`, atomically. It evaluates like the original; training cannot resume from it."""
    source = Path(source)
    saved = load_saved(source)
    infos = {
        "observation_layout": [list(t) for t in saved_layout(source, saved)],
        "config": OmegaConf.to_container(run_config(source, saved)),
    }
    slim = {k: saved[k] for k in EVALUATION_KEYS if k in saved} | {"infos": infos}
    with atomic_path(Path(target)) as tmp:
        torch.save(slim, tmp)
    return Path(target)


def _infos(saved: dict) -> dict:
    return saved.get("infos") or {}


def saved_layout(checkpoint: Path, saved: dict) -> list[tuple[str, int]]:
    """The observation layout a checkpoint was trained on: the one it carries, or the side file
    of an older run."""
    stored = _infos(saved).get("observation_layout")
    if stored is None:
        layout_file = Path(checkpoint).parent / LAYOUT_FILE
        if not layout_file.is_file():
            raise RealIkeaError(
                f"{checkpoint}: carries no observation layout and has no {LAYOUT_FILE} beside "
                "it; not a Real-IKEA run"
            )
        stored = json.loads(layout_file.read_text())
    return [(str(name), int(size)) for name, size in stored]


def check_layout(checkpoint: Path, saved: dict) -> None:
    """Refuse to resume training from a checkpoint trained on another observation layout."""
    stored = saved_layout(checkpoint, saved)
    if stored != list(observations.LAYOUT):
        raise RealIkeaError(
            f"{checkpoint}: trained on observation layout {stored}, this code uses "
            f"{list(observations.LAYOUT)}"
        )


def run_config(checkpoint: Path, saved: dict | None = None) -> DictConfig:
    """The training config of the run a checkpoint belongs to: the one it carries, or (older
    runs) Hydra's .hydra/config.yaml beside it."""
    saved = load_saved(checkpoint) if saved is None else saved
    if "config" in _infos(saved):
        return OmegaConf.create(_infos(saved)["config"])
    path = Path(checkpoint).parent / ".hydra" / "config.yaml"
    if not path.is_file():
        raise RealIkeaError(f"{checkpoint}: carries no config and has none at {path}")
    return OmegaConf.load(path)


class CheckpointPolicy:
    """The actor MLP of a checkpoint; `act` maps observations (N, observations.SIZE) to actions
    (N, 5), reading the terms of the layout the checkpoint was trained on: its mean action, or
    with `sample_seed` given, a sample of its Gaussian (its learned std) drawn from that seed."""

    name = "checkpoint"

    def __init__(self, path: Path, sample_seed: int | None = None):
        path = Path(path)
        self.noise = None if sample_seed is None else torch.Generator().manual_seed(sample_seed)
        saved = load_saved(path)
        layout = saved_layout(path, saved)
        try:
            self.index = observations.selector(layout)
        except KeyError as err:
            raise RealIkeaError(
                f"{path}: trained on an observation layout this code cannot give: {err.args[0]}"
            ) from err
        self.run_cfg = run_config(path, saved)
        agent = self.run_cfg.agent
        state = saved["actor_state_dict"]
        dummy = TensorDict({"policy": torch.zeros(1, len(self.index))}, batch_size=[1])
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
        """`policy.path` names the checkpoint (relative paths from the repository root);
        `policy.sample` acts on samples drawn from the run's seed (`env.seed`)."""
        if not cfg.policy.path:
            raise RealIkeaError("policy=checkpoint needs policy.path=PATH/model_<it>.pt")
        sample = cfg.policy.get("sample", False)
        if not isinstance(sample, bool):
            raise RealIkeaError(f"policy.sample={sample}: use true or false")
        return cls(repo_path(cfg.policy.path), int(cfg.env.seed) if sample else None)

    def reset(self, env_ids, facts) -> None:
        """Stateless: nothing to forget between episodes (and no privileged scene facts)."""

    @torch.inference_mode()
    def act(self, obs: np.ndarray) -> np.ndarray:
        batch = torch.as_tensor(np.asarray(obs)[:, self.index], dtype=torch.float32)
        td = TensorDict({"policy": batch}, batch_size=[batch.shape[0]])
        mean = self.actor(td)
        if self.noise is not None:
            std = self.actor.distribution.std_param.clamp(min=1e-6)
            mean = mean + std * torch.randn(mean.shape, generator=self.noise)
        return mean.numpy().astype(np.float64)
