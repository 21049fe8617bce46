"""`realikea train [Hydra overrides and flags]`: the same composition as `python train.py`.

Everything after `train` goes to Hydra unparsed (its flags, such as `-m`, `--cfg job` or
`--help`, included), so `realikea.cli` hands it over before its own argument parsing."""

from __future__ import annotations

import argparse
import sys

from realikea.training.main import main

HELP = "train PPO: Hydra overrides and flags, as for python train.py (see realikea train --help)"


def register(parser: argparse.ArgumentParser) -> None:
    """Listed in `realikea --help`; the arguments themselves are Hydra's (`run_train`)."""
    parser.set_defaults(run=lambda args: run_train([]))


def run_train(arguments: list[str]) -> int:
    """Run Hydra's training entry point on `arguments`, which Hydra reads from sys.argv."""
    sys.argv = ["realikea train", *arguments]
    main()
    return 0
