"""`realikea train [Hydra overrides and flags]`: the same composition as `python train.py`.

Everything after `train` goes to Hydra unparsed (its flags, such as `-m`, `--cfg job` or
`--help`, included), so `realikea.cli` hands it over before its own argument parsing."""

from __future__ import annotations

import sys

HELP = "train PPO: Hydra overrides and flags, as for python train.py (see realikea train --help)"


def run_train(arguments: list[str]) -> int:
    """Run Hydra's training entry point on `arguments`, which Hydra reads from sys.argv."""
    from realikea.training.main import main  # torch and rsl-rl: 3 s, only when training

    sys.argv = ["realikea train", *arguments]
    main()
    return 0
