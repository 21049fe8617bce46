"""Run the fidelity grid (realikea/conf/experiment/fidelity_grid.yaml) two runs at a time and
keep each finished run in experiments/fidelity_ablation/results/grid/NAME/ (grid_runs.py says
what a run keeps; realikea/training/queue.py how runs resume).

    python experiments/fidelity_ablation/grid.py                     # every run not yet kept
    python experiments/fidelity_ablation/grid.py --seeds 0 --categories two_point --dry-run
    python experiments/fidelity_ablation/grid.py --paper --seeds 0 1 2   # switch 900, 1,500 its
"""

from __future__ import annotations

import argparse
import sys

from grid_runs import AXES, grid_queue, planned

from realikea.errors import RealIkeaError


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for axis, values in AXES.items():
        parser.add_argument(f"--{axis}", nargs="+", default=list(values))
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    parser.add_argument("--paper", action="store_true", help="switch at 900, 1,500 iterations")
    parser.add_argument("--jobs", type=int, default=2, help="runs side by side (2 cores: 2)")
    parser.add_argument("--dry-run", action="store_true", help="print the commands only")
    args = parser.parse_args()
    try:
        runs = planned(args.collisions, args.resistances, args.categories, args.seeds, args.paper)
    except RealIkeaError as err:
        parser.error(str(err))
    queue = grid_queue()
    if args.dry_run:
        queue.show(runs)
        return 0
    return queue.run_all(runs, args.jobs)


if __name__ == "__main__":
    sys.exit(main())
