"""What an evaluation runs with: the composed config (a checkpoint's own run groups, the held-out
split by default) and the policy, then episodes on an env pool."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from omegaconf import DictConfig, OmegaConf

from realikea.assets.split import with_default_split
from realikea.config import check_settings, load_config, overrides_set
from realikea.errors import RealIkeaError
from realikea.eval.protocol import EvalResult, run_episodes
from realikea.policies.registry import make_policy
from realikea.pool.env_pool import EnvPool
from realikea.tasks.open_task import OpenTask
from realikea.tasks.start_state import CURRICULUM_KEYS

# groups a checkpoint brings from its own run unless the command line overrides them
RUN_GROUPS = ("gripper", "contact", "sim", "task", "agent")
MIRROR_KEY = "task.mirror_doors"  # realikea/tasks/mirror.py
# what a run's overrides say of the configurations it trained on (not carried by a checkpoint)
CELL_KEYS = ("asset", "asset.kind", "collision", "resistance", "scene")


def trained_cell(run: Path) -> list[str]:
    """The overrides of a Hydra run folder (`.hydra/overrides.yaml`) that name what it trained
    on: its parts, kind, collision source, resistance and scene."""
    path = Path(run) / ".hydra" / "overrides.yaml"
    if not path.is_file():
        raise RealIkeaError(f"{run}: no Hydra overrides at {path}")
    return [o for o in OmegaConf.load(path) if o.split("=")[0] in CELL_KEYS]


def effective_config(cfg: DictConfig, run_cfg: DictConfig, overrides: list[str]) -> DictConfig:
    """The eval config with the run's robot, gripper, contact and task unless overridden; not
    the run's start-state curriculum (every evaluated episode starts at home). The run's
    `task.mirror_doors` is the frame its policy acts in, kept unless that key is overridden."""
    merged = OmegaConf.to_container(cfg, resolve=True)
    for group in RUN_GROUPS:
        if group in run_cfg and not overrides_set(overrides, group):
            merged[group] = OmegaConf.to_container(run_cfg[group], resolve=True)
    for key in CURRICULUM_KEYS:
        merged["task"].pop(key, None)
    if not overrides_set(overrides, MIRROR_KEY):
        merged["task"]["mirror_doors"] = bool(OmegaConf.select(run_cfg, MIRROR_KEY))
    return OmegaConf.create(merged)


def eval_overrides_with_split(overrides: list[str]) -> list[str]:
    """The evaluation draws from the held-out parts: `asset.split=test` unless `overrides` set
    asset.split (train, test or all)."""
    return with_default_split(overrides, "test")


def eval_setup(overrides: list[str]):
    """(cfg, policy) of `realikea eval OVERRIDES`: the composed config with a checkpoint's own
    run groups (`effective_config`) or a policy's own configuration, the classifier on
    (eval.yaml: contacts); the test split unless the overrides name one."""
    cfg = load_config(eval_overrides_with_split(overrides), "eval")
    check_settings(cfg)  # episodes, envs, ... in range before a policy loads
    policy = make_policy(cfg)
    if hasattr(policy, "run_interactive") and not overrides_set(overrides, "asset.split"):
        cfg.asset.split = "train"  # teleop records demonstrations: training data, not a test
    if hasattr(policy, "run_cfg"):
        cfg = effective_config(cfg, policy.run_cfg, overrides)
    if hasattr(policy, "configure"):  # e.g. replay: the recorded configuration and seed
        cfg = policy.configure(cfg, overrides)
    if cfg.task.get("mirror_doors") and not hasattr(policy, "run_cfg"):
        raise RealIkeaError(
            f"task.mirror_doors=true reflects what a learned policy observes; policy="
            f"{cfg.policy.name} plans on the scene's facts, which it does not reflect"
        )
    return cfg, policy


def evaluate(
    cfg: DictConfig, policy, progress: bool = True, task_factory: Callable = OpenTask
) -> EvalResult:
    """`cfg.episodes` episodes of `policy` on an env pool of at most `cfg.env.num_envs` envs
    running `task_factory`'s tasks (e.g. `RecordingTask`, whose episodes carry their steps)."""
    episodes = int(cfg.episodes)
    if episodes < 1:
        raise RealIkeaError(f"episodes={episodes}: use 1 or more")
    cfg.env.num_envs = min(episodes, int(cfg.env.num_envs))
    with EnvPool.from_config(cfg, task_factory=task_factory) as pool:
        return run_episodes(pool, policy, episodes, progress=progress)
