"""`realikea eval [run|table|sweep|rerun|failures] ...`: `run` (the default: `realikea eval
OVERRIDES`) evaluates a policy over episodes (Fail/Partial/Success and a JSON line), `table` the
Table 2 grid (realikea/eval/table.py), `sweep DIR` every checkpoint of a run
(realikea/eval/sweep.py), `rerun DIR ...` a run's end-of-training evaluation again
(realikea/eval/runs.py), `failures` the failure classifier on episodes built to fail
(realikea/eval/failure_cases.py)."""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from realikea.assets.catalog import effective_split
from realikea.errors import RealIkeaError
from realikea.eval.failure_cases import validate
from realikea.eval.protocol import outcome_table
from realikea.eval.record import record_demonstration, recording_target, write_recording
from realikea.eval.runs import rerun
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.sweep import run_sweep
from realikea.eval.table import run_table
from realikea.eval.video import VIDEO_BY, record_draw
from realikea.tasks.open_task import OpenTask
from realikea.tasks.recording import RecordingTask

SUBCOMMANDS = ("run", "table", "sweep", "rerun", "failures")
OVERRIDES_HELP = "Hydra overrides, e.g. asset=two_point resistance=high episodes=50"


def with_default_command(argv: list[str]) -> list[str]:
    """`eval OVERRIDES` is `eval run OVERRIDES` (an eval command line as typed, without `eval`)."""
    if argv[:1] and (argv[0] in SUBCOMMANDS or argv[0].startswith("-")):
        return argv
    return ["run", *argv]


def register(parser: argparse.ArgumentParser) -> None:
    """Add the eval sub-commands to `parser`."""
    commands = parser.add_subparsers(
        dest="command", required=True, metavar="{" + ",".join(SUBCOMMANDS) + "}"
    )
    run = commands.add_parser(
        "run", help="a policy over episodes (the default command: `realikea eval OVERRIDES`)"
    )
    run.add_argument(
        "overrides", nargs="*", help="Hydra overrides, e.g. policy=checkpoint "
        "policy.path=RUN/model_500.pt asset=two_point resistance=high episodes=50 video=true",
    )  # fmt: skip
    run.set_defaults(run=run_eval)
    table = commands.add_parser("table", help="the paper's Table 2: policies x categories x modes")
    table.add_argument("overrides", nargs="*", help=OVERRIDES_HELP)
    table.set_defaults(run=lambda args: run_table(args.overrides))
    sweep = commands.add_parser("sweep", help="every checkpoint of a run under the three modes")
    sweep.add_argument("run_dir", type=Path, help="a training run's directory")
    sweep.add_argument("overrides", nargs="*", help=OVERRIDES_HELP)
    sweep.set_defaults(run=lambda args: run_sweep(args.run_dir, args.overrides))
    again = commands.add_parser("rerun", help="repeat runs' end-of-training evaluation")
    again.add_argument("run_dirs", nargs="+", type=Path, help="training run directories")
    again.add_argument(
        "--collision", help="evaluate on this collision geometry instead of the spec's, into "
        "eval_<collision>.json (eval.json untouched)",
    )  # fmt: skip
    again.set_defaults(run=lambda args: rerun(args.run_dirs, args.collision))
    failures = commands.add_parser("failures", help="the failure modes on episodes built to fail")
    failures.add_argument("--episodes", type=int, default=20, help="episodes per case")
    failures.add_argument("--seed", type=int, default=1000, help="the configurations' draw")
    failures.add_argument("--out", type=Path, help="also write the table to this markdown file")
    failures.set_defaults(run=lambda args: validate(args.episodes, args.seed, args.out))


def run_eval(args: argparse.Namespace) -> int:
    """`realikea eval [run] OVERRIDES`: the outcome table, the JSON line last; `record=DIR` also
    writes the episodes as a LeRobot dataset (a teleop session's demonstration, replayed)."""
    cfg, policy = eval_setup(args.overrides)
    record = recording_target(cfg)  # a bad folder stops here, before any episode runs
    if cfg.video and cfg.video_by not in VIDEO_BY:
        raise RealIkeaError(f"video_by={cfg.video_by}: use one of {', '.join(VIDEO_BY)}")
    if hasattr(policy, "run_interactive"):  # e.g. teleop: one env in-process, in a viewer
        if record is not None and getattr(policy, "record", None) is None:
            raise RealIkeaError(
                "record=DIR with policy=teleop converts the session's demonstration: "
                "add policy.record=FILE.npz"
            )
        code = int(policy.run_interactive(cfg, args.overrides))
        if record is not None:
            dataset = record_demonstration(policy.record, record, cfg.paths.library)
            print(f"LeRobot dataset: {dataset}")
        return code
    result = evaluate(cfg, policy, task_factory=OpenTask if record is None else RecordingTask)
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
        record_draw(cfg, policy, Path(cfg.video_path or "outputs/eval.mp4"))
    if record is not None:
        print(f"LeRobot dataset: {write_recording(result, cfg, record)}")
    print(json.dumps({**result.summary(), "split": split}))
    return 0
