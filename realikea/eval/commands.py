"""`realikea eval [table|sweep|rerun] [overrides]`: a policy over episodes, Fail/Partial/Success
and a JSON line; `table` runs the Table 2 grid (realikea/eval/table.py), `sweep run=DIR` every
checkpoint of a run (realikea/eval/sweep.py), `rerun run=DIR ...` a run's end-of-training
evaluation again (realikea/eval/runs.py)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from realikea.assets.catalog import effective_split
from realikea.assets.library import training_configurations
from realikea.eval.protocol import outcome_table
from realikea.eval.runs import rerun
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.sweep import run_sweep
from realikea.eval.table import run_table
from realikea.eval.video import record_strategies
from realikea.tasks.open_task import OpenTask


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
        return run_table(args.overrides[1:])
    if args.overrides and args.overrides[0] == "sweep":
        return run_sweep(args.overrides[1:])
    if args.overrides and args.overrides[0] == "rerun":
        return rerun(args.overrides[1:])
    return run_eval(args)


def run_eval(args: argparse.Namespace) -> int:
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
        paths = training_configurations(cfg, int(cfg.video_episodes), int(cfg.env.seed))
        tasks = [OpenTask(cfg, p, int(cfg.env.seed) + i) for i, p in enumerate(paths)]
        stem = Path(cfg.video_path or "outputs/eval.mp4")
        for label, path in record_strategies(tasks, policy, int(cfg.video_episodes), stem).items():
            print(f"video ({label}): {path}")
    print(json.dumps({**result.summary(), "split": split}))
    return 0
