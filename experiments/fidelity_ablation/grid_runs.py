"""The fidelity grid's runs (realikea/conf/experiment/fidelity_grid.yaml): which runs the axes
select, seed by seed, and what a finished run keeps; trained two at a time by the run queue.

A run is finished once its eval.json exists (`train.eval_after`) and then kept in KEPT/NAME: its
Hydra config, metrics, eval.json (its commands naming the checkpoint git holds), the final
checkpoint slimmed to the actor, and the wall time of every launch. NAME is
<collision>_<resistance>_<category>_s<seed>, with a `paper_` prefix for the paper's schedule.
Seed 0 of the paper's schedule on two-point x high also keeps its checkpoints every SWEEP_EVERY
iterations (slim, about 0.2 MB each), so the appendix's checkpoint selection can be rerun from
git (`realikea eval sweep`, on the validation draw).
"""

from __future__ import annotations

import itertools
import json
from dataclasses import dataclass
from pathlib import Path

from realikea.errors import RealIkeaError
from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE, shown_path
from realikea.training.queue import QueuedRun, RunQueue, keep_run

KEPT = WORKSPACE / "experiments/fidelity_ablation/results/grid"
WORK = WORKSPACE / "outputs/fidelity_grid"
AXES = {  # the grid's axes as the options name them, in the order the runs go
    "collisions": ("coacd", "hull"),
    "resistances": ("high", "smooth", "normal"),
    "categories": ("two_point", "knob", "finger_pull"),
}
ITERATIONS = 900  # fidelity_grid.yaml's agent.max_iterations
PAPER = {"dr.switch_iteration": 900, "agent.max_iterations": 1500}  # the paper's schedule
SWEEP_EVERY = 100  # iterations between the checkpoints a swept run keeps (1,500 its: 16 kept)
SWEPT_CELL = ("two_point", "high")  # (category, resistance) of the swept runs
DONE = "eval.json"  # written by the run's end-of-training evaluation


@dataclass(frozen=True)
class GridRun(QueuedRun):
    """One training run of the grid: the queue's run with its cell, seed and schedule."""

    collision: str = ""
    resistance: str = ""
    category: str = ""
    seed: int = 0
    paper: bool = False

    @property
    def swept(self) -> bool:
        """Whether the run keeps checkpoints for the sweep: one paper-scale run per source, of
        the paper's cell (two-point x high); other cells at the paper's schedule keep their
        last checkpoint only."""
        return self.paper and self.seed == 0 and (self.category, self.resistance) == SWEPT_CELL


def grid_run(collision: str, resistance: str, category: str, seed: int, paper: bool) -> GridRun:
    stem = f"{collision}_{resistance}_{category}_s{seed}"
    overrides = [
        "+experiment=fidelity_grid",
        f"collision={collision}",
        f"resistance={resistance}",
        f"asset={category}",
        f"env.seed={seed}",
    ]
    overrides += [f"{k}={v}" for k, v in PAPER.items()] if paper else []
    iterations = PAPER["agent.max_iterations"] if paper else ITERATIONS
    name = f"paper_{stem}" if paper else stem
    return GridRun(name, tuple(overrides), iterations, collision, resistance, category, seed, paper)


def planned(collisions, resistances, categories, seeds, paper: bool = False) -> list[GridRun]:
    """The runs the axes select, seed by seed (every cell has a seed before any has two);
    unknown axis values and negative seeds are errors."""
    given = {"collisions": collisions, "resistances": resistances, "categories": categories}
    for axis, values in AXES.items():
        bad = [v for v in given[axis] if v not in values]
        if bad:
            raise RealIkeaError(f"unknown {axis} {', '.join(bad)}: use {', '.join(values)}")
    if any(s < 0 for s in seeds):
        raise RealIkeaError(f"seeds must be >= 0, got {list(seeds)}")
    cells = list(itertools.product(categories, resistances, collisions))
    return [
        grid_run(collision, resistance, category, seed, paper)
        for seed in seeds
        for category, resistance, collision in cells
    ]


def keep(run: GridRun, seconds: list[float], work: Path = WORK, kept: Path = KEPT) -> Path:
    """Keep the finished run from `work` in `kept`/NAME (the queue's `keep_run`): also its
    eval.json, naming the kept checkpoint, and for a swept run the sweep's checkpoints."""
    source, target = work / run.name, kept / run.name
    report = kept_eval(json.loads((source / DONE).read_text()), target)
    return keep_run(
        source, target, seconds, kept_checkpoints(run, checkpoints(source)),
        {DONE: json.dumps(report, indent=2) + "\n"},
    )  # fmt: skip


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


def grid_queue(work: Path = WORK, kept: Path = KEPT) -> RunQueue:
    """The grid's run queue: runs train in `work`, finish with their eval.json and are kept
    under `kept`."""
    return RunQueue(
        work,
        lambda run: DONE,
        lambda run, seconds: keep(run, seconds, work, kept),
        lambda run: (kept / run.name / DONE).is_file(),
    )
