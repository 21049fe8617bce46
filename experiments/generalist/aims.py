"""The generalist's aims (registered in README.md, "The aims"): `python train.py` on seeds
200-202 and the design card's `python train.py collision=hull resistance=high` on seeds
210-212, each run alone on the machine, kept, then evaluated on the held-out parts.

    python experiments/generalist/aims.py                      # resumable: training, then cells
    python experiments/generalist/aims.py --recipes default --seeds 200 --dry-run
    python experiments/generalist/aims.py --park               # stopped runs into git

Trains in outputs/generalist_aims/NAME (the run queue: realikea/training/queue.py), kept in
results/<recipe>/s<seed>/ (slim last checkpoint, metrics, config, wall time, learning curve).
Each kept run is evaluated before the next trains (kitchen, test parts, 50 randomized episodes
a cell on draw 1000, `evaluate_grid`): `default` in smooth and high on CoACD
(results/default/s<seed>/cells.jsonl); `hull_high` in high on its own hull
(results/hull_high/s<seed>_own/cells.jsonl) and on CoACD (results/hull_high/s<seed>/cells.jsonl).
Then its frames in high, the first success and the first failure of four episodes per category x
kind (`frames.sh`, on its own hull for `hull_high`), into results/<recipe>/s<seed>/frames/.
`python experiments/generalist/aims_report.py` writes the verdicts.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from contextlib import nullcontext
from pathlib import Path

from train_gated import RESULTS, kept_dir

from realikea.assets.catalog import CATEGORIES
from realikea.config import load_config
from realikea.eval.library_grid import KINDS, evaluate_grid
from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE
from realikea.reports.learning_curve import plot_learning_curve
from realikea.training.pipeline import final_iterations, pipelined
from realikea.training.queue import QueuedRun, RunQueue, keep_run

PARKED = RESULTS / "aims_parked"
WORK = WORKSPACE / "outputs/generalist_aims"
# python train.py's defaults (a pipeline of teachers and one student: realikea/conf/asset/all.yaml);
# the superseded defaults' runs of these seeds are in results/<recipe>_group_ppo/ (round 1's),
# results/default_student_96/ (round 18's), results/default_fine_tune/ (round 19's),
# results/default_validated_marks/ (round 21's), results/default_student_mean/ (round 23's),
# results/default_student_noise/ (round 24's) and results/<recipe>_judged_high/ (round 25's)
RECIPES = {"default": (), "hull_high": ("collision=hull", "resistance=high")}
SEEDS = {"default": (200, 201, 202), "hull_high": (210, 211, 212)}
# evaluations of a kept run: results folder suffix -> (resistance modes, extra eval overrides)
EVALUATIONS = {
    "default": {"": (("smooth", "high"), ())},
    "hull_high": {"_own": (("high",), ("collision=hull",)), "": (("high",), ())},
}
FRAMES = {"default": (), "hull_high": ("collision=hull",)}  # overrides of each recipe's frames
FRAME_EPISODES = 4
GROUPS = tuple((kind, category) for kind in KINDS for category in CATEGORIES)  # (kind, category)


def aim_run(recipe: str, seed: int) -> QueuedRun:
    """The recipe's command on one seed, as long as its composed config says (in stages if it
    trains a pipeline)."""
    overrides = (*RECIPES[recipe], f"env.seed={seed}", "logger=none")
    cfg = load_config(overrides)
    return QueuedRun(f"{recipe}_s{seed}", overrides, final_iterations(cfg), staged=pipelined(cfg))


def keep(run: QueuedRun, seconds: list[float]) -> Path:
    """Keep the run (`keep_run`, with its stages) and plot its per-group learning curve beside
    it."""
    kept = keep_run(WORK / run.name, kept_dir(run), seconds, staged=run.staged)
    plot_learning_curve(kept)
    return kept


def queue() -> RunQueue:
    return RunQueue(
        WORK,
        lambda run: f"model_{run.iterations - 1}.pt",
        keep,
        lambda run: (kept_dir(run) / "wall.json").is_file(),
        parked=PARKED,
    )


def evaluate(run: QueuedRun) -> None:
    """Every cell of the run's evaluations not yet in its cells.jsonl files."""
    recipe = run.name.rsplit("_", 1)[0]
    folder = kept_dir(run)
    checkpoint = checkpoints(folder)[-1][1]
    for suffix, (modes, extra) in EVALUATIONS[recipe].items():
        cells = folder.with_name(folder.name + suffix) / "cells.jsonl"
        print(f"evaluate {run.name} -> {cells.relative_to(WORKSPACE)}", flush=True)
        evaluate_grid(checkpoint, cells, modes=modes, extra=list(extra))


def record_frames(run: QueuedRun) -> None:
    """The run's frames (`frames.sh`), unless its frames folder holds some of every group."""
    recipe = run.name.rsplit("_", 1)[0]
    folder = kept_dir(run)
    if all(any((folder / "frames").glob(f"{kind}_{category}_*.png")) for kind, category in GROUPS):
        return
    name = str(folder.relative_to(RESULTS))
    command = ["bash", str(Path(__file__).with_name("frames.sh")), name, "drawer door flap",
               str(FRAME_EPISODES), "outcome", *FRAMES[recipe]]  # fmt: skip
    print(f"frames {run.name} -> {folder.relative_to(WORKSPACE)}/frames", flush=True)
    subprocess.run(command, check=True)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--recipes", nargs="+", choices=list(RECIPES), default=list(RECIPES))
    parser.add_argument("--seeds", nargs="+", type=int, help="default: each recipe's own three")
    parser.add_argument("--dry-run", action="store_true", help="print the runs and stop")
    parser.add_argument("--park", action="store_true", help="stop at next checkpoints; copy to git")
    args = parser.parse_args(argv)
    if args.seeds and any(s < 0 for s in args.seeds):
        parser.error(f"seeds must be >= 0, got {args.seeds}")
    runs = [aim_run(r, s) for r in args.recipes for s in (args.seeds or SEEDS[r])]
    runs_queue = queue()
    training = not (args.dry_run or args.park)
    # one driver across runs and evaluations, so a park made during an evaluation stops the rest
    with runs_queue.driving(runs) if training else nullcontext():
        for run in runs:
            status = runs_queue.serve([run], 1, dry_run=args.dry_run, park=args.park)
            if status:
                return status
            if training and runs_queue.kept(run):
                evaluate(run)
                record_frames(run)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
