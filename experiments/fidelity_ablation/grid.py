"""Run the fidelity grid (realikea/conf/experiment/fidelity_grid.yaml) two runs at a time and
keep each finished run in experiments/fidelity_ablation/grid/NAME/: its Hydra config, metrics,
eval.json, the final checkpoint slimmed to the actor, and the wall time of every launch.

    python experiments/fidelity_ablation/grid.py                     # every run not yet kept
    python experiments/fidelity_ablation/grid.py --seeds 0 --categories two_point --dry-run
    python experiments/fidelity_ablation/grid.py --paper --seeds 0 1 2   # switch 900, 1,500 its

A run is kept once its eval.json exists; a stopped run (outputs/fidelity_grid/NAME with
checkpoints, no eval.json) continues from its last checkpoint (`train.resume=`) for the
iterations it still lacks, appending to its metrics.csv. A run whose training process is alive
(outputs/fidelity_grid/NAME.pid) is left to it, so two drivers never train the same run.
Each launch's wall time is written to outputs/fidelity_grid/NAME.wall.json as it runs (every
poll), so a launch stopped with the session still counts in the compute table.
Runs go seed by seed, so every cell has one seed before any has two. NAME is
<collision>_<resistance>_<category>_s<seed>, with a `paper_` prefix for the paper's schedule.
Seed 0 of the paper's schedule on two-point x high also keeps its checkpoints every SWEEP_EVERY
iterations (slim, about 0.2 MB each), so the appendix's checkpoint selection can be rerun from git:
`realikea eval sweep experiments/fidelity_ablation/grid/paper_<collision>_high_two_point_s0`.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from realikea.errors import RealIkeaError
from realikea.eval.sweep import checkpoints
from realikea.files import atomic_write_text, shown_path
from realikea.policies.checkpoint import slim_checkpoint
from realikea.training.metrics import join_launches

ROOT = Path(__file__).resolve().parents[2]
KEPT = ROOT / "experiments/fidelity_ablation/grid"
WORK = ROOT / "outputs/fidelity_grid"
AXES = {  # the grid's axes as the options name them, in the order the runs go
    "collisions": ("coacd", "hull"),
    "resistances": ("high", "smooth", "normal"),
    "categories": ("two_point", "knob", "finger_pull"),
}
ITERATIONS = 900  # fidelity_grid.yaml's agent.max_iterations
PAPER = {"dr.switch_iteration": 900, "agent.max_iterations": 1500}  # the paper's schedule
POLL_SECONDS = 10.0  # how often the driver checks its runs and records their wall time
SWEEP_EVERY = 100  # iterations between the checkpoints a swept run keeps (1,500 its: 16 kept)
SWEPT_CELL = ("two_point", "high")  # (category, resistance) of the swept runs


@dataclass(frozen=True)
class GridRun:
    """One training run of the grid: its cell, seed and schedule."""

    collision: str
    resistance: str
    category: str
    seed: int
    paper: bool = False

    @property
    def name(self) -> str:
        stem = f"{self.collision}_{self.resistance}_{self.category}_s{self.seed}"
        return f"paper_{stem}" if self.paper else stem

    @property
    def swept(self) -> bool:
        """Whether the run keeps checkpoints for the sweep: one paper-scale run per source, of
        the issue's paper cell (two-point x high); other cells at the paper's schedule keep
        their last checkpoint only."""
        return self.paper and self.seed == 0 and (self.category, self.resistance) == SWEPT_CELL

    @property
    def iterations(self) -> int:
        return PAPER["agent.max_iterations"] if self.paper else ITERATIONS

    def overrides(self) -> list[str]:
        out = [
            "+experiment=fidelity_grid",
            f"collision={self.collision}",
            f"resistance={self.resistance}",
            f"asset={self.category}",
            f"env.seed={self.seed}",
        ]
        return out + ([f"{k}={v}" for k, v in PAPER.items()] if self.paper else [])


def planned(args: argparse.Namespace) -> list[GridRun]:
    """The runs the arguments select, seed by seed; unknown axis values are errors."""
    for axis, values in AXES.items():
        bad = [v for v in getattr(args, axis) if v not in values]
        if bad:
            raise RealIkeaError(f"unknown {axis} {', '.join(bad)}: use {', '.join(values)}")
    if any(s < 0 for s in args.seeds):
        raise RealIkeaError(f"seeds must be >= 0, got {args.seeds}")
    cells = list(itertools.product(args.categories, args.resistances, args.collisions))
    return [
        GridRun(collision, resistance, category, seed, args.paper)
        for seed in args.seeds
        for category, resistance, collision in cells
    ]


def command(run: GridRun) -> list[str]:
    """The train.py command of `run`, continuing from its last checkpoint if it has one."""
    out = [sys.executable, str(ROOT / "train.py"), *run.overrides()]
    out.append(f"hydra.run.dir={WORK / run.name}")
    found = checkpoints(WORK / run.name) if any((WORK / run.name).glob("model_*.pt")) else []
    if found:
        last, path = found[-1]
        out += [f"train.resume={path}", f"agent.max_iterations={run.iterations - last}"]
    return out


def keep(run: GridRun, seconds: list[float]) -> Path:
    """Copy what re-evaluation and the report need from the finished run to KEPT/NAME."""
    source, target = WORK / run.name, KEPT / run.name
    staging = target.with_name(target.name + ".partial")
    shutil.rmtree(staging, ignore_errors=True)
    shutil.copytree(source / ".hydra", staging / ".hydra")
    report = kept_eval(json.loads((source / "eval.json").read_text()), target)
    atomic_write_text(staging / "eval.json", json.dumps(report, indent=2) + "\n")
    metrics = (source / "metrics.csv").read_text().splitlines()
    atomic_write_text(staging / "metrics.csv", "\n".join(join_launches(metrics)) + "\n")
    for path in kept_checkpoints(run, checkpoints(source)):
        slim_checkpoint(path, staging / path.name)
    atomic_write_text(staging / "wall.json", json.dumps({"launches_seconds": seconds}) + "\n")
    shutil.rmtree(target, ignore_errors=True)
    staging.rename(target)
    return target


def kept_eval(report: dict, target: Path) -> dict:
    """`report` (an eval.json) with each mode's command naming the checkpoint kept in `target`,
    relative to the repository, instead of the one in outputs/ that git does not hold."""
    shown = shown_path(target / report["checkpoint"])
    for entry in report["modes"].values():
        entry["command"] = " ".join(
            f"policy.path={shown}" if token.startswith("policy.path=") else token
            for token in entry["command"].split(" ")
        )
    return report


def kept_checkpoints(run: GridRun, found: list[tuple[int, Path]]) -> list[Path]:
    """The checkpoints `keep` copies of the run's (iteration, path) list: the last one, and for
    a swept run also those every SWEEP_EVERY iterations."""
    last = found[-1]
    every = [f for f in found[:-1] if f[0] % SWEEP_EVERY == 0] if run.swept else []
    return [path for _, path in [*every, last]]


def running(run: GridRun) -> bool:
    """Whether a training process of `run` (its pid file) is alive."""
    pid_file = WORK / f"{run.name}.pid"
    if not pid_file.is_file():
        return False
    try:
        os.kill(int(pid_file.read_text()), 0)
    except (ProcessLookupError, ValueError):
        return False
    return True


def launch(run: GridRun) -> subprocess.Popen:
    WORK.mkdir(parents=True, exist_ok=True)
    log = (WORK / f"{run.name}.log").open("a")
    print(f"start {run.name}: {' '.join(command(run)[1:])}", flush=True)
    proc = subprocess.Popen(command(run), cwd=ROOT, stdout=log, stderr=subprocess.STDOUT)
    atomic_write_text(WORK / f"{run.name}.pid", f"{proc.pid}\n")
    return proc


def wall_times(run: GridRun) -> list[float]:
    """Wall seconds of the run's launches so far (the running one's as of the last poll)."""
    path = WORK / f"{run.name}.wall.json"
    return json.loads(path.read_text()) if path.is_file() else []


def record_wall(run: GridRun, seconds: list[float]) -> None:
    atomic_write_text(WORK / f"{run.name}.wall.json", json.dumps(seconds) + "\n")


def run_all(runs: list[GridRun], jobs: int) -> int:
    """Launch the runs `jobs` at a time; keep each that finishes with its eval.json."""
    queue = [r for r in runs if not (KEPT / r.name / "eval.json").is_file()]
    print(f"{len(runs) - len(queue)} of {len(runs)} runs already kept; {len(queue)} to go")
    active: dict[GridRun, tuple[subprocess.Popen, float, list[float]]] = {}
    failed = 0
    while queue or active:
        while queue and len(active) < jobs:
            run = queue.pop(0)
            if running(run):
                print(f"skip {run.name}: being trained by another process", flush=True)
                continue
            if (WORK / run.name / "eval.json").is_file():  # trained and evaluated, not kept
                print(f"kept {keep(run, wall_times(run))}", flush=True)
                continue
            active[run] = (launch(run), time.time(), wall_times(run))
        time.sleep(POLL_SECONDS)
        for run, (proc, begin, earlier) in list(active.items()):
            seconds = [*earlier, time.time() - begin]
            record_wall(run, seconds)
            if proc.poll() is None:
                continue
            del active[run]
            if proc.returncode == 0 and (WORK / run.name / "eval.json").is_file():
                print(f"kept {keep(run, seconds)} ({seconds[-1] / 60:.1f} min)", flush=True)
            else:
                failed += 1
                print(f"FAILED {run.name} (exit {proc.returncode}): {WORK / run.name}.log")
    return 1 if failed else 0


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
        runs = planned(args)
    except RealIkeaError as err:
        parser.error(str(err))
    if args.dry_run:
        for run in runs:
            state = "kept" if (KEPT / run.name / "eval.json").is_file() else "to run"
            state = "running" if running(run) else state
            print(f"{state}: " + " ".join(command(run)[1:]))
        return 0
    return run_all(runs, args.jobs)


if __name__ == "__main__":
    sys.exit(main())
