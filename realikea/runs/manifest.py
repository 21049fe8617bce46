"""A study's committed checkpoints as a manifest (`<study>/results/checkpoints.csv`): each file's
SHA-256, size, iteration, whether training can resume from it, and the command that made it.

The command is the run's own record: Hydra's `.hydra/hydra.yaml` (its command-line overrides and
its `hydra.*` ones), else `.hydra/overrides.yaml`. A run kept before runs carried a record is
looked up in the study's hand-written `results/checkpoint_commands.yaml` (run folder, relative to
`results/`, -> command). A resumed launch's record is the launch that wrote the checkpoint; its
`train.resume=` names where it continued from, also given as `resumed_from`. A stage of a staged
run (training/pipeline.py: a folder of a run that holds stages.json or whose recorded config
names a pipeline) was made by that run's launch.
"""

from __future__ import annotations

import csv
import hashlib
import io
import shlex
from pathlib import Path

import yaml

from realikea.errors import RealIkeaError
from realikea.eval.sweep import checkpoint_iteration
from realikea.files import atomic_write_text
from realikea.policies.checkpoint import load_saved
from realikea.training.queue import STAGES

MANIFEST = "results/checkpoints.csv"
COMMANDS = "results/checkpoint_commands.yaml"
COLUMNS = ("checkpoint", "iteration", "bytes", "sha256", "resumable", "command", "resumed_from")
HYDRA_ADDS = {"hydra.mode=RUN"}  # an override Hydra records that nobody typed


def study_checkpoints(study: Path) -> list[Path]:
    """Every `model_<iteration>.pt` under the study's results folder, sorted."""
    found = (study / "results").rglob("model_*.pt")
    return sorted(p for p in found if checkpoint_iteration(p.name) is not None)


def sha256(path: Path) -> str:
    """The file's SHA-256, hex."""
    digest = hashlib.sha256()
    with path.open("rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def recorded_overrides(run: Path) -> list[str] | None:
    """The run's command-line overrides as Hydra recorded them, or None without a record."""
    hydra_file, overrides_file = run / ".hydra/hydra.yaml", run / ".hydra/overrides.yaml"
    if hydra_file.is_file():
        overrides = yaml.safe_load(hydra_file.read_text())["hydra"]["overrides"]
        typed = [o for o in overrides.get("hydra", []) if o not in HYDRA_ADDS]
        return typed + list(overrides.get("task", []))
    if overrides_file.is_file():
        return list(yaml.safe_load(overrides_file.read_text()) or [])
    return None


def run_command(study: Path, run: Path, commands: dict[str, str]) -> str:
    """The command that made the run: its Hydra record, its staged run's (a stage), else the
    study's hand-written one."""
    overrides = recorded_overrides(run)
    if overrides is not None:
        return shlex.join(["python", "train.py", *overrides])
    if staged_run(run.parent):
        return run_command(study, run.parent, commands)
    key = run.relative_to(study / "results").as_posix()
    if key not in commands:
        raise RealIkeaError(
            f"{run}: no Hydra record (.hydra/) and no entry '{key}' in {study / COMMANDS}"
        )
    return commands[key]


def staged_run(run: Path) -> bool:
    """Whether the folder is a staged run's (its stages.json, or its recorded config names a
    pipeline, whether chosen on the command line or by a default), whose folders are its
    stages."""
    config = run / ".hydra/config.yaml"
    recorded = (yaml.safe_load(config.read_text()) or {}) if config.is_file() else {}
    pipeline = (recorded.get("pipeline") or {}).get("name", "none")
    return (run / STAGES).is_file() or pipeline != "none"


def resumed_from(command: str) -> str:
    """The checkpoint a launch continued from (its `train.resume=`), or ''."""
    resumes = [w.split("=", 1)[1] for w in shlex.split(command) if w.startswith("train.resume=")]
    return resumes[-1] if resumes else ""


def manifest_rows(study: Path) -> list[dict[str, str]]:
    """One row per committed checkpoint of the study (`COLUMNS`), by path."""
    commands_file = study / COMMANDS
    commands = (yaml.safe_load(commands_file.read_text()) or {}) if commands_file.is_file() else {}
    rows = []
    for path in study_checkpoints(study):
        command = run_command(study, path.parent, commands)
        rows.append(
            {
                "checkpoint": path.relative_to(study).as_posix(),
                "iteration": str(checkpoint_iteration(path.name)),
                "bytes": str(path.stat().st_size),
                "sha256": sha256(path),
                "resumable": "yes" if "optimizer_state_dict" in load_saved(path) else "no",
                "command": command,
                "resumed_from": resumed_from(command),
            }
        )
    return rows


def manifest_text(rows: list[dict[str, str]]) -> str:
    """The manifest's CSV text."""
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return out.getvalue()


def write_manifest(study: Path) -> Path:
    """Write the study's manifest (atomically) and return its path."""
    path = study / MANIFEST
    atomic_write_text(path, manifest_text(manifest_rows(study)))
    return path


def read_manifest(study: Path) -> list[dict[str, str]]:
    """The study's manifest as written, [] if it has none."""
    path = study / MANIFEST
    if not path.is_file():
        return []
    with path.open(newline="") as f:
        return list(csv.DictReader(f))
