"""Finished runs on disk: their config, evaluation, training metrics and wall time."""

from __future__ import annotations

import json
from pathlib import Path

from omegaconf import OmegaConf

from realikea.errors import RealIkeaError
from realikea.eval.sweep import checkpoint_iteration
from realikea.tasks.randomization import two_phase_switch
from realikea.training.metrics import read_metrics

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
    """Wall seconds of every launch of a run (the run queue's wall.json: training, resumes
    and evaluation), empty for runs made without it."""
    path = Path(run_dir) / "wall.json"
    return json.loads(path.read_text())["launches_seconds"] if path.is_file() else []


def train_seconds(run: dict) -> float | None:
    """eval.json's train_seconds, else the sum of rsl-rl's per-iteration collection+learning."""
    seconds = run["eval"].get("train_seconds")
    if seconds is not None:
        return float(seconds)
    parts = [run["metrics"].get(f"Perf/{k}_time", ([], []))[1] for k in ("collection", "learning")]
    return float(sum(map(sum, parts))) if any(parts) else None


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
