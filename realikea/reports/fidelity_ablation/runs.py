"""Finished runs on disk: their config, evaluation, training metrics and wall time."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from omegaconf import OmegaConf

from realikea.errors import RealIkeaError
from realikea.eval.sweep import checkpoint_iteration
from realikea.tasks.randomization import two_phase_switch
from realikea.training.metrics import read_metrics

SUCCESS_WINDOW = 20  # iterations averaged for "training success reached 50 %" and the curves
# iterations per window of the plateau check (training success over the last window against
# the one before): a grid run should train until its success has plateaued
PLATEAU_WINDOW = 100
EVAL_COMMAND = "realikea eval"  # how eval.json and cells.jsonl store an evaluation's command


def unfinished_runs(roots: list[Path]) -> list[Path]:
    """Run directories (a `.hydra/config.yaml`) under the roots without an eval.json yet."""
    return sorted(
        config.parent.parent
        for root in roots
        for config in Path(root).rglob(".hydra/config.yaml")
        if not (config.parent.parent / "eval.json").is_file()
    )


def find_runs(roots: list[Path]) -> list[dict]:
    """One dict per finished run: its cell, eval.json, metrics and frame strips."""
    for root in roots:
        if not Path(root).is_dir():
            raise RealIkeaError(f"{root}: no such directory of runs")
    runs = []
    for root in roots:
        for eval_file in sorted(Path(root).rglob("eval.json")):
            run_dir = eval_file.parent
            config = run_dir / ".hydra" / "config.yaml"
            if not config.is_file():
                continue
            cfg = OmegaConf.load(config)
            metrics = run_dir / "metrics.csv"
            report = json.loads(eval_file.read_text())
            runs.append(
                {
                    "dir": run_dir,
                    "collision": str(cfg.collision.source),
                    "resistance": str(cfg.resistance.name),
                    "category": str(cfg.asset.category),
                    "gripper": str(cfg.gripper.name),
                    "contact": str(cfg.contact.name),
                    "seed": int(cfg.env.seed),
                    "launch_iterations": int(cfg.agent.max_iterations),
                    "iterations": _trained_iterations(report, int(cfg.agent.max_iterations)),
                    "num_envs": int(cfg.env.num_envs),
                    "switch": two_phase_switch(cfg.get("dr")),
                    "eval": report,
                    "scene": str(cfg.get("scene", {}).get("name", "freestanding")),
                    "metrics": read_metrics(run_dir) if metrics.is_file() else {},
                    "strips": sorted((run_dir / "videos").glob("*.png")),
                    "wall": _launch_seconds(run_dir),
                }
            )
    return runs


def _trained_iterations(report: dict, launch_iterations: int) -> int:
    """Iterations behind the checkpoint eval.json evaluated (model_<i>.pt: i + 1): a resumed
    run's config holds only its last launch's count."""
    iteration = checkpoint_iteration(report.get("checkpoint", ""))
    return launch_iterations if iteration is None else iteration + 1


def schedule(run: dict) -> str:
    """A run's training schedule: its iterations and, with two-phase randomization, the switch."""
    switch = f", switch {run['switch']}" if run.get("switch") is not None else ""
    return f"{run['iterations']} its{switch}"


def _launch_seconds(run_dir: Path) -> list[float]:
    """Wall seconds of every launch of a run (experiments/fidelity_ablation/grid.py's
    wall.json: training, resumes and evaluation), empty for runs made without it."""
    path = Path(run_dir) / "wall.json"
    return json.loads(path.read_text())["launches_seconds"] if path.is_file() else []


def train_seconds(run: dict) -> float | None:
    """eval.json's train_seconds, else the sum of rsl-rl's per-iteration collection+learning."""
    seconds = run["eval"].get("train_seconds")
    if seconds is not None:
        return float(seconds)
    parts = [run["metrics"].get(f"Perf/{k}_time", ([], []))[1] for k in ("collection", "learning")]
    return float(sum(map(sum, parts))) if any(parts) else None


def iterations_to_success(
    run: dict, level: float = 0.5, window: int = SUCCESS_WINDOW
) -> int | None:
    """The first iteration from which the training success, averaged over the next `window`
    iterations, reaches `level` (None if it never does). A window counts only when it is full,
    ending at or before the run's last iteration: the mean of a run's last few iterations, a
    window cut off by the end of training, never counts as learned."""
    its, values = (np.asarray(x) for x in run["metrics"].get("/episode/success", ([], [])))
    for start in np.unique(its):
        if start + window - 1 > its.max():  # the window runs past the last iteration
            break
        chosen = (its >= start) & (its < start + window)
        if values[chosen].mean() >= level:
            return int(start)
    return None


def last_windows(
    run: dict, tag: str, window: int = PLATEAU_WINDOW
) -> tuple[float | None, float | None]:
    """The mean of a training metric over the last `window` iterations and its change from the
    `window` before them (None where a window has no iteration): a plateau changes little."""
    its, values = (np.asarray(x) for x in run["metrics"].get(tag, ([], [])))
    if its.size == 0:
        return None, None
    end = its.max() + 1
    last = values[its >= end - window]
    before = values[(its >= end - 2 * window) & (its < end - window)]
    mean = float(last.mean())
    return mean, (mean - float(before.mean())) if before.size else None


def trailing_mean(its, values, window: int) -> tuple[np.ndarray, np.ndarray]:
    """The mean of `values` over each `window` consecutive iterations, at the window's last
    iteration (nothing before a full window)."""
    its, values = np.asarray(its), np.asarray(values, float)
    if len(values) < window:
        return its[:0], values[:0]
    order = np.argsort(its, kind="stable")
    its, values = its[order], values[order]
    # summed, then divided: a window of exactly half successes averages 0.5, as in
    # iterations_to_success, not a rounding error below it
    means = np.convolve(values, np.ones(window), mode="valid") / window
    return its[window - 1 :], means


def command_overrides(command: str) -> list[str]:
    """The overrides of a stored `realikea eval OVERRIDES` command line."""
    tokens = command.split()
    if tokens[:2] != EVAL_COMMAND.split():
        raise RealIkeaError(f"not a `{EVAL_COMMAND}` command: {command!r}")
    return tokens[2:]


def read_eval(run: Path) -> dict:
    """The run's eval.json modes; a directory without one is an error naming it."""
    path = run / "eval.json"
    if not path.is_file():
        raise RealIkeaError(f"{run}: no eval.json (not a finished run)")
    return json.loads(path.read_text())["modes"]


def mode_overrides(run: Path, resistance: str, episodes: int) -> list[str]:
    """The `realikea eval` overrides of a finished run's evaluation (its eval.json) in
    `resistance`, with `episodes` episodes."""
    modes = read_eval(run)
    if resistance not in modes:
        raise RealIkeaError(f"{run}: evaluated in {', '.join(modes)}, not {resistance}")
    tokens = command_overrides(modes[resistance]["command"])
    return [t for t in tokens if not t.startswith("episodes=")] + [f"episodes={episodes}"]
