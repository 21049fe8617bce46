"""PPO training of the opening task with rsl-rl's OnPolicyRunner, from a composed Hydra config."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from rsl_rl.runners import OnPolicyRunner

from realikea.assets.library import TrainingDraw, built_models, training_draw
from realikea.config import check_settings
from realikea.errors import RealIkeaError
from realikea.policies.checkpoint import check_layout, checkpoint_infos, load_saved, run_config
from realikea.pool.env_pool import EnvPool
from realikea.pool.rsl_rl_env import RslRlVecEnv
from realikea.rewards import reward_from_config, variant_name
from realikea.tasks.start_state import AjarStart, PregraspStart
from realikea.training.distillation import (
    check_teachers,
    distillation_config,
    distilling,
    teacher_paths,
)
from realikea.training.rotating_draw import RotatingDraw
from realikea.training.success_draw import SuccessFollowingDraw

GROUP_PPO = "realikea.training.group_ppo:GroupPPO"


def algorithm_class(agent: DictConfig) -> str:
    """rsl-rl's PPO, or with `agent.group_advantages` (absent: off) `GroupPPO`, which normalises
    advantages per task group."""
    return GROUP_PPO if agent.get("group_advantages") else "PPO"


def runner_config(cfg: DictConfig, label: str = "", line: int = 0) -> dict:
    """The rsl-rl train_cfg dict built from `cfg.agent` and `cfg.logger`; `label` names the
    launch on its progress bar (a pipeline's stage), shown on the terminal's `line` (stages
    side by side)."""
    agent = cfg.agent
    distribution = {"class_name": "GaussianDistribution", "init_std": float(agent.init_std)}
    low, high = agent.get("min_std"), agent.get("max_std")
    floor = 1e-6 if low is None else float(low)  # unset: rsl-rl's own clamp range
    ceiling = 1e6 if high is None else float(high)
    if low is not None and not 0.0 < floor <= float(agent.init_std):
        raise RealIkeaError(
            f"agent.min_std={low}: use a value in (0, agent.init_std={agent.init_std}] or null"
        )
    if ceiling < floor:
        raise RealIkeaError(
            f"agent.max_std={high}: use a value of at least agent.min_std ({floor:g}) or null"
        )
    if low is not None or high is not None:
        distribution["std_range"] = [floor, ceiling]  # rsl-rl clamps the std to it
    model = {"class_name": "MLPModel", "activation": str(agent.activation)}
    return {
        "num_steps_per_env": int(agent.num_steps_per_env),
        "save_interval": int(agent.save_interval),
        "obs_groups": {"actor": ["policy"], "critic": ["critic"]},
        "algorithm": {
            "class_name": algorithm_class(agent),
            **OmegaConf.to_container(agent.algorithm),
        },
        "actor": {
            **model,
            "hidden_dims": list(agent.actor_hidden_dims),
            "obs_normalization": bool(agent.empirical_normalization),
            "distribution_cfg": distribution,
        },
        "critic": {
            **model,
            "hidden_dims": list(agent.critic_hidden_dims),
            "obs_normalization": bool(agent.empirical_normalization),
        },
        "logger": {
            "class_name": "realikea.training.log_writer:RealIkeaLogWriter",
            "backend": str(cfg.logger.backend),
            **({"project_name": str(cfg.logger.project)} if "project" in cfg.logger else {}),
            **({"iterations": int(agent.max_iterations)} if cfg.train.console == "bar" else {}),
            **({"description": label} if label and cfg.train.console == "bar" else {}),
            **({"line": line} if line and cfg.train.console == "bar" else {}),
        },
        "check_for_nan": True,
    }


class Runner(OnPolicyRunner):
    """rsl-rl's runner whose every checkpoint carries `infos` (the observation layout and the
    run's resolved config: `checkpoint_infos`), so a checkpoint evaluates without its run folder."""

    def __init__(self, *args, infos: dict, **kwargs):
        super().__init__(*args, **kwargs)
        self.infos = infos

    def save(self, path: str, infos: dict | None = None) -> None:
        super().save(path, {**self.infos, **(infos or {})})


def check_reward_variant(path: Path, saved: dict, cfg: DictConfig) -> None:
    """Refuse to resume a run under another reward variant than the one it was trained on."""
    trained = variant_name(run_config(path, saved).task.reward)
    asked = variant_name(cfg.task.reward)
    if trained != asked:
        raise RealIkeaError(
            f"{path}: trained on the {trained!r} reward variant, this run asks for {asked!r}; "
            f"resume with task/reward={trained} or start a new run"
        )


def check_resumable(path: Path, cfg: DictConfig) -> None:
    """Refuse, before any work, a checkpoint that is missing, corrupt, trained on another
    observation layout or under another reward variant than `cfg` asks for."""
    path = Path(path)
    saved = load_saved(path)
    check_layout(path, saved)
    check_reward_variant(path, saved, cfg)


def load_checkpoint(runner: OnPolicyRunner, path: Path) -> None:
    """Load weights and optimizer state (`check_resumable` first)."""
    try:
        runner.load(str(path))
    except Exception as err:  # torch raises many types for truncated or foreign files
        raise RealIkeaError(f"{path}: cannot be loaded as an rsl-rl checkpoint ({err})") from err


def check_init_actor(cfg: DictConfig) -> None:
    """Refuse a `train.init_actor` that is missing, unreadable, on another observation layout,
    or given with `train.resume` (which restores the actor itself)."""
    path = Path(cfg.train.init_actor)
    if cfg.train.resume:
        raise RealIkeaError(
            f"train.init_actor={path} with train.resume: a resumed run restores its own actor"
        )
    check_layout(path, load_saved(path))


def init_actor(runner: OnPolicyRunner, path: Path) -> None:
    """Start the policy (weights, action std, observation normaliser) from the actor of the
    checkpoint at `path` (`check_init_actor` first); the critic and the optimiser start fresh."""
    try:
        runner.alg.get_policy().load_state_dict(load_saved(path)["actor_state_dict"])
    except RuntimeError as err:
        raise RealIkeaError(
            f"train.init_actor={path}: its actor does not match this run's network ({err})"
        ) from err


CONSOLES = ("bar", "report")


@contextlib.contextmanager
def console(cfg: DictConfig, run_dir: Path) -> Iterator[None]:
    """Where rsl-rl's per-iteration report goes: RUN/iterations.log under the progress bar
    (`train.console=bar`), stdout otherwise."""
    if cfg.train.console == "report":
        yield
        return
    with (
        (run_dir / "iterations.log").open("a", buffering=1) as log,
        contextlib.redirect_stdout(log),
    ):
        yield


def check_inputs(cfg: DictConfig) -> SuccessFollowingDraw | RotatingDraw | TrainingDraw:
    """Every check of a launch's inputs that needs no simulation (settings in range, the reward
    variant, the console, a resumable checkpoint, a non-empty draw of configurations); returns
    the draw (not yet built)."""
    check_settings(cfg)
    reward_from_config(OmegaConf.to_container(cfg.task.reward))  # a bad variant fails here
    PregraspStart.from_config(cfg.task)  # a bad share or group too
    AjarStart.from_config(cfg.task)  # and a bad range
    if cfg.train.console not in CONSOLES:
        raise RealIkeaError(f"train.console={cfg.train.console}: use one of {', '.join(CONSOLES)}")
    if cfg.train.resume:
        check_resumable(Path(cfg.train.resume), cfg)
    if cfg.train.get("init_actor"):
        check_init_actor(cfg)
    n, seed = int(cfg.env.num_envs), int(cfg.env.seed)
    if cfg.asset.get("rotate_every") is not None:
        draw = RotatingDraw.from_config(cfg, n, seed)
    elif cfg.asset.get("follow_success") is not None:
        draw = SuccessFollowingDraw.from_config(cfg, n, seed)
    else:
        draw = training_draw(cfg, n, seed)
    if distilling(cfg):
        check_teachers(cfg, env_groups(draw))
    return draw


def env_groups(draw: SuccessFollowingDraw | RotatingDraw | TrainingDraw) -> list[str]:
    """Each env's category x kind group; none for a success-following draw, which moves envs
    between groups as it goes (a rotating draw keeps them)."""
    return [] if isinstance(draw, SuccessFollowingDraw) else [c.group for c in draw.configurations]


def train_config(cfg: DictConfig, label: str = "", line: int = 0) -> dict:
    """rsl-rl's train_cfg: PPO's (`runner_config`), or the distillation's when the run distils
    teachers (`distill.teachers`, checked by `check_inputs`)."""
    ppo = runner_config(cfg, label, line)
    return distillation_config(cfg, ppo, teacher_paths(cfg)) if distilling(cfg) else ppo


def train(cfg: DictConfig, run_dir: Path, label: str = "", line: int = 0) -> Path:
    """Train for `cfg.agent.max_iterations`; returns the last checkpoint in `run_dir`. `label`
    names the launch on its progress bar, shown on the terminal's `line`."""
    run_dir = Path(run_dir)
    draw = check_inputs(cfg)
    torch.set_num_threads(int(cfg.train.torch_threads))
    torch.manual_seed(int(cfg.env.seed))
    np.random.seed(int(cfg.env.seed))
    moving = draw if isinstance(draw, SuccessFollowingDraw | RotatingDraw) else None
    pool = EnvPool(cfg, moving.paths() if moving else built_models(cfg, draw.configurations))
    try:
        env = RslRlVecEnv(
            pool,
            cfg,
            int(cfg.agent.num_steps_per_env),
            draw=moving,
            labels=draw.labels,
            groups=env_groups(draw),
        )
        runner = Runner(
            env,
            train_config(cfg, label, line),
            log_dir=str(run_dir),
            device=cfg.train.device,
            infos=checkpoint_infos(cfg),
        )
        if cfg.train.resume:
            load_checkpoint(runner, Path(cfg.train.resume))
            env.set_iteration(runner.current_learning_iteration)
        elif cfg.train.get("init_actor"):
            init_actor(runner, Path(cfg.train.init_actor))
        with console(cfg, run_dir):
            runner.learn(
                int(cfg.agent.max_iterations),
                init_at_random_ep_len=bool(cfg.agent.init_at_random_ep_len),
            )
    finally:
        pool.close()
    return run_dir / f"model_{runner.current_learning_iteration}.pt"
