"""`realikea eval [table|sweep|rerun] [overrides]`: a policy over episodes, Fail/Partial/Success
and a JSON line; `table` runs the Table 2 grid (realikea/eval/table.py), `sweep run=DIR` every
checkpoint of a run (realikea/eval/sweep.py), `rerun run=DIR ...` a run's end-of-training
evaluation again (realikea/training/eval_after.py)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from omegaconf import DictConfig, OmegaConf

from realikea.assets.split import effective_split, override_key, with_default_split
from realikea.config import load_config
from realikea.errors import RealIkeaError

# groups a checkpoint brings from its own run unless the command line overrides them
RUN_GROUPS = ("gripper", "contact", "sim", "task", "agent")


def register(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "overrides",
        nargs="*",
        help="optionally `table`, `sweep` or `rerun` first, then Hydra overrides, e.g. "
        "policy=checkpoint policy.path=RUN/model_500.pt asset=two_point resistance=high "
        "episodes=50 video=true",
    )
    parser.set_defaults(run=dispatch)


def dispatch(args: argparse.Namespace) -> int:
    """`eval table ...`, `eval sweep ...`, `eval rerun ...` or a plain `eval ...`."""
    if args.overrides and args.overrides[0] == "table":
        from realikea.eval.table import run_table

        return run_table(args.overrides[1:])
    if args.overrides and args.overrides[0] == "sweep":
        from realikea.eval.sweep import run_sweep

        return run_sweep(args.overrides[1:])
    if args.overrides and args.overrides[0] == "rerun":
        from realikea.training.eval_after import rerun

        return rerun(args.overrides[1:])
    return run_eval(args)


def effective_config(cfg: DictConfig, run_cfg: DictConfig, overrides: list[str]) -> DictConfig:
    """The eval config with the run's robot, gripper, contact and task unless overridden."""
    merged = OmegaConf.to_container(cfg, resolve=True)
    for group in RUN_GROUPS:
        if group in run_cfg and not any(o.lstrip("+~").startswith(group) for o in overrides):
            merged[group] = OmegaConf.to_container(run_cfg[group], resolve=True)
    # the strategy classifier belongs to the evaluation, not to the run
    merged["task"]["contacts"] = OmegaConf.to_container(cfg.task.contacts, resolve=True)
    return OmegaConf.create(merged)


def eval_overrides_with_split(overrides: list[str]) -> list[str]:
    """The evaluation draws from the held-out parts: `asset.split=test` unless `overrides` set
    asset.split (train, test or all)."""
    return with_default_split(overrides, "test")


def eval_setup(overrides: list[str]):
    """(cfg, policy) of `realikea eval OVERRIDES`: the composed config with a checkpoint's own
    run groups (`effective_config`) or a policy's own configuration, contacts logged; the test
    split unless the overrides name one (`eval_overrides_with_split`)."""
    from realikea.policies.registry import make_policy

    cfg = load_config(eval_overrides_with_split(overrides))
    policy = make_policy(cfg)
    if hasattr(policy, "run_interactive") and not any(
        override_key(o) == "asset.split" for o in overrides
    ):
        cfg.asset.split = "train"  # teleop records demonstrations: training data, not a test
    if hasattr(policy, "run_cfg"):
        cfg = effective_config(cfg, policy.run_cfg, overrides)
    if hasattr(policy, "configure"):  # e.g. replay: the recorded configuration and seed
        cfg = policy.configure(cfg, overrides)
    cfg.task.contacts.log = True  # the strategy classifier needs the contact forces
    return cfg, policy


def evaluate(cfg: DictConfig, policy, progress: bool = True):
    """`cfg.episodes` episodes of `policy` on an env pool of at most `cfg.env.num_envs` envs."""
    from realikea.eval.protocol import run_episodes
    from realikea.pool.env_pool import EnvPool

    episodes = int(cfg.episodes)
    if episodes < 1:
        raise RealIkeaError(f"episodes={episodes}: use 1 or more")
    cfg.env.num_envs = min(episodes, int(cfg.env.num_envs))
    with EnvPool.from_config(cfg) as pool:
        return run_episodes(pool, policy, episodes, progress=progress)


def run_eval(args: argparse.Namespace) -> int:
    from realikea.eval.protocol import outcome_table

    cfg, policy = eval_setup(args.overrides)
    if hasattr(policy, "run_interactive"):  # e.g. teleop: one env in-process, in a viewer
        return int(policy.run_interactive(cfg, args.overrides))
    result = evaluate(cfg, policy)
    split = effective_split(cfg.asset)
    print(
        f"policy {cfg.policy.name} on asset={cfg.asset.category} split={split}"
        f" resistance={cfg.resistance.name} collision={cfg.collision.source}"
        f" gripper={cfg.gripper.name} contact={cfg.contact.name}"
    )
    print(outcome_table(result))
    for note, n in result.summary().get("policy_notes", {}).items():  # failures with a reason
        print(f"no motion planned in {n} episode(s): {note}")
    if cfg.video:
        from realikea.assets.library import training_configurations
        from realikea.eval.video import record_strategies
        from realikea.tasks.open_task import OpenTask

        paths = training_configurations(cfg, int(cfg.video_episodes), int(cfg.env.seed))
        tasks = [OpenTask(cfg, p, int(cfg.env.seed) + i) for i, p in enumerate(paths)]
        stem = Path(cfg.video_path or "outputs/eval.mp4")
        for label, path in record_strategies(tasks, policy, int(cfg.video_episodes), stem).items():
            print(f"video ({label}): {path}")
    print(json.dumps({**result.summary(), "split": split}))
    return 0
