"""The policies' action spread and where their episodes ended, run by run: the kept screen runs
(experiments/reward_screen/results/runs/) and the rescue runs stopped for time before 400
iterations (experiments/reward_screen/results/stopped/, their metrics and Hydra overrides copied
from outputs/).
Prints a markdown table.

    python experiments/reward_screen/exploration.py

Columns: the policy's mean action standard deviation (`Policy/mean_std`) at iterations 20, 60,
120 and the last logged one, and the share of episodes ending in each stage at that last
iteration (`/end_stage/<k>`, averaged over its last SUCCESS_WINDOW iterations).
"""

from __future__ import annotations

import argparse

from realikea.files import WORKSPACE
from realikea.runs.curves import SUCCESS_WINDOW, trailing_mean
from realikea.training.metrics import read_metrics

FOLDERS = [WORKSPACE / "experiments/reward_screen/results" / name for name in ("runs", "stopped")]
AT = (20, 60, 120)  # iterations at which the spread is shown


def main(argv: list[str] | None = None) -> int:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    print("| run | folder | std at " + ", ".join(map(str, AT)) + ", last (its) | "
          "end stage 1 / 2 / 3 / 4, last 20 its |")  # fmt: skip
    print("|---|---|---|---|")
    for folder in FOLDERS:
        for run in sorted(p for p in folder.iterdir() if (p / "metrics.csv").is_file()):
            metrics = read_metrics(run)
            its, stds = metrics["Policy/mean_std"]
            by_it = dict(zip(its, stds, strict=True))
            spread = [f"{by_it[i]:.2f}" if i in by_it else "-" for i in AT]
            spread.append(f"{stds[-1]:.2f} ({its[-1]})")
            ends = [
                trailing_mean(*metrics[f"/end_stage/{k}"], SUCCESS_WINDOW)[1][-1]
                for k in (1, 2, 3, 4)
            ]
            print(
                f"| {run.name} | {folder.name} | {', '.join(spread)} | "
                f"{' / '.join(f'{e:.2f}' for e in ends)} |"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
