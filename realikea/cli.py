"""The `realikea` console command: one sub-command group per concern."""

from __future__ import annotations

import argparse
import sys

from realikea.assets import commands as asset_commands
from realikea.errors import RealIkeaError
from realikea.eval import commands as eval_commands
from realikea.export import commands as export_commands
from realikea.fidelity import commands as fidelity_commands
from realikea.training import commands as training_commands


def build_parser() -> argparse.ArgumentParser:
    """Assemble the argument parser from each group's `register` function."""
    parser = argparse.ArgumentParser(prog="realikea", description=__doc__)
    groups = parser.add_subparsers(
        dest="group", required=True, metavar="{assets,fidelity,train,eval}"
    )
    assets = asset_commands.register(
        groups.add_parser("assets", help="build, inspect and export the asset library")
    )
    export_commands.register(assets)
    fidelity_commands.register(
        groups.add_parser("fidelity", help="collision-mesh fidelity metric and reports")
    )
    groups.add_parser("train", help=training_commands.HELP)  # `main` hands it to Hydra
    eval_commands.register(
        groups.add_parser("eval", help="evaluate a policy: Fail/Partial/Success")
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; user errors print one clear line and exit 2."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["train"]:  # Hydra parses its own command line
        return training_commands.run_train(argv[1:])
    if argv[:1] == ["eval"]:
        argv = ["eval", *eval_commands.with_default_command(argv[1:])]
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except RealIkeaError as err:
        print(f"realikea: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
