"""End-of-training evaluation (`train.eval_after`): the run's last checkpoint under several
resistance modes through `realikea eval`'s own code, written to `<run>/eval.json`.

`realikea eval rerun DIR [DIR ...]` repeats it for finished runs (after a change to the
evaluation, e.g. the classifier), from the run's own config and command line.

Each mode is exactly `realikea eval <the run's command-line overrides> asset.split=<split>
policy=checkpoint [collision=...] policy.path=<checkpoint> resistance=<mode> episodes=<n>
[dr=...] [env.seed=...]` (the command is stored beside its result, so any entry can be re-run by
hand). `train.eval_after.collision` evaluates on that geometry whatever the run trained on (the
fidelity grid: `coacd`, the faithful one); unset, on the run's own.

The split (`train.eval_after.split`: train, test or all) defaults to `test`, the parts held out
of training (realikea/catalog/split.csv). A run made before the split existed (its config has no
asset.split) is re-evaluated on `all`, as it was then.
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

from omegaconf import DictConfig, OmegaConf

from realikea.assets.catalog import effective_split
from realikea.assets.split import check_split_value
from realikea.config import load_config, overrides_set
from realikea.errors import RealIkeaError
from realikea.eval.setup import eval_overrides_with_split, eval_setup, evaluate
from realikea.eval.sweep import checkpoints
from realikea.eval.table import contact_means, pulled
from realikea.files import CONF_DIR, atomic_write_text, repo_path
from realikea.provenance import result_versions

EVAL_FILE = "eval.json"
# run overrides the evaluation replaces or that only concern training
_DROPPED = ("resistance", "policy", "episodes", "video", "train", "logger", "asset.split")
DEFAULT_SPLIT = "test"  # evaluate on the held-out parts unless train.eval_after.split says


def eval_split(spec: DictConfig, default: str = DEFAULT_SPLIT) -> str:
    """The split an evaluation spec draws from: spec.split, else `default`."""
    return check_split_value(spec.get("split") or default)


def eval_overrides(
    run_overrides: list[str],
    checkpoint: Path,
    mode: str,
    spec: DictConfig,
    default_split: str = DEFAULT_SPLIT,
) -> list[str]:
    """The `realikea eval` overrides of one mode (see the module docstring)."""
    dropped = list(_DROPPED)
    if spec.get("collision"):
        dropped.append("collision")
    if spec.get("dr"):
        dropped.append("dr")
    if spec.get("seed") is not None:
        dropped.append("env.seed")
    kept = [o for o in run_overrides if not any(overrides_set([o], d) for d in dropped)]
    out = [*kept, f"asset.split={eval_split(spec, default_split)}", "policy=checkpoint"]
    if spec.get("collision"):
        out.append(f"collision={spec.collision}")
    out += [f"policy.path={Path(checkpoint).resolve()}"]
    out += [f"resistance={mode}", f"episodes={int(spec.episodes)}"]
    if spec.get("dr"):
        out.append(f"dr={spec.dr}")
    if spec.get("seed") is not None:
        out.append(f"env.seed={int(spec.seed)}")
    return out


def check_eval_spec(
    spec: DictConfig, run_overrides: list[str], default_split: str = DEFAULT_SPLIT
) -> None:
    """Compose every mode's evaluation config before training starts, so a bad
    `train.eval_after` (a collision, split, dr or mode that does not exist, no episodes) fails
    in seconds instead of after the run."""
    try:
        if int(spec.get("episodes") or 0) < 1:
            raise RealIkeaError(f"episodes={spec.get('episodes')}: use 1 or more")
        if not spec.get("resistances"):
            raise RealIkeaError("resistances: name at least one mode (smooth, normal, high)")
        for mode in spec.resistances:
            overrides = eval_overrides(
                run_overrides, Path("model.pt"), str(mode), spec, default_split
            )
            load_config(eval_overrides_with_split(overrides), "eval")
    except RealIkeaError as err:
        raise RealIkeaError(f"train.eval_after: {err}") from err


def _finite(value: float) -> float | None:
    return None if value is None or math.isnan(value) else float(value)


def contact_record(episodes: list[dict]) -> dict:
    """The contact statistics of an evaluation's JSON: their means over the episodes with a
    pulling phase (null without one) and how many episodes that is."""
    return {
        "contacts": {s: _finite(v) for s, v in contact_means(episodes).items()},
        "pulled_episodes": len(pulled(episodes)),
    }


def evaluate_run(
    spec: DictConfig,
    run_dir: Path,
    checkpoint: Path,
    run_overrides: list[str],
    train_seconds: float | None = None,
    default_split: str = DEFAULT_SPLIT,
    eval_file: str = EVAL_FILE,
) -> dict:
    """Evaluate `checkpoint` under every mode of `spec.resistances` on the parts of
    `spec.split` (else `default_split`); write and return `eval_file` (eval.json)."""
    run_dir = Path(run_dir)
    report: dict = {
        "checkpoint": Path(checkpoint).name,
        "train_seconds": train_seconds,
        "episodes": int(spec.episodes),
        "split": eval_split(spec, default_split),
        "modes": {},
    }
    begin = time.perf_counter()
    for mode in spec.resistances:
        overrides = eval_overrides(run_overrides, checkpoint, str(mode), spec, default_split)
        cfg, policy = eval_setup(overrides)
        result = evaluate(cfg, policy, progress=False)
        report["modes"][str(mode)] = {
            **result.summary(),
            **contact_record(result.episodes),
            "mean_return": _finite(
                sum(e.get("episode_return", 0.0) for e in result.episodes) / len(result.episodes)
            ),
            "split": effective_split(cfg.asset),
            "dr": str(cfg.dr.mode),
            "env_seed": int(cfg.env.seed),
            "command": "realikea eval " + " ".join(overrides),
        }
        print(f"eval_after {mode}: {json.dumps(result.summary())}", flush=True)
    report["eval_seconds"] = time.perf_counter() - begin
    report["spec"] = OmegaConf.to_container(spec, resolve=True)
    report["versions"] = result_versions()
    atomic_write_text(run_dir / eval_file, json.dumps(report, indent=2) + "\n")
    return report


def rerun_split(hydra: Path) -> str:
    """The default split of a rerun: test for a run whose config has asset.split (made with the
    held-out split), all for an older run, whose evaluation drew from every part."""
    asset = OmegaConf.load(Path(hydra) / "config.yaml").get("asset") or {}
    return DEFAULT_SPLIT if "split" in asset else "all"


def run_scene(hydra: Path) -> list[str]:
    """The scene overrides that re-evaluate a run where it was trained: `scene=freestanding` for
    a run made before the kitchen scene existed; in the kitchen, the run's own per-category
    placements where they are not today's default (none for a run made before them: every
    configuration's arm 0.80 m below its handle) and its command line did not set them."""
    hydra = Path(hydra)
    scene = OmegaConf.load(hydra / "config.yaml").get("scene")
    if scene is None:
        return ["scene=freestanding"]
    robot = scene.get("robot")
    overrides = hydra / "overrides.yaml"
    given = overrides.is_file() and any(
        str(o).startswith("scene.robot.placements=") for o in OmegaConf.load(overrides)
    )
    if not robot or given:
        return []
    placements = robot.get("placements")
    placements = OmegaConf.to_container(placements) if placements else []
    default = OmegaConf.load(CONF_DIR / "scene" / f"{scene.name}.yaml").robot.get("placements")
    if placements == OmegaConf.to_container(default or []):
        return []
    return [f"scene.robot.placements={_override_value(placements)}"]


def _override_value(value) -> str:
    """A value in Hydra's override grammar (flow style, bare keys, quoted strings)."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_override_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_override_value(v) for v in value) + "]"
    return json.dumps(value)


def rerun(runs: list[Path], collision: str | None = None) -> int:
    """`realikea eval rerun [--collision SOURCE] DIR [DIR ...]`: evaluate each run's last
    checkpoint again with the run's `train.eval_after` and command line, rewriting DIR/eval.json
    (training time kept); on the run's split (`rerun_split`) unless its spec names one. With
    `collision`, on that geometry instead of the spec's, into DIR/eval_<collision>.json (eval.json
    untouched): a hull-trained run on its own hull beside the protocol's CoACD. Every run is
    checked before the first is evaluated."""
    planned = [_rerun_plan(repo_path(run), collision) for run in runs]
    eval_file = f"eval_{collision}.json" if collision else EVAL_FILE
    for run, spec, checkpoint, run_overrides, seconds, split in planned:
        print(f"eval rerun {run.name}: {checkpoint.name}", flush=True)
        evaluate_run(spec, run, checkpoint, run_overrides, seconds, split, eval_file)
    return 0


def _rerun_plan(run: Path, collision: str | None) -> tuple:
    """(run, spec, checkpoint, overrides, training seconds, split) of one rerun, its spec
    composed for every mode (a bad run or collision fails here, before any evaluation)."""
    hydra = run / ".hydra"
    if not (hydra / "config.yaml").is_file() or not (hydra / "overrides.yaml").is_file():
        raise RealIkeaError(f"{run}: not a training run (no .hydra/{{config,overrides}}.yaml)")
    spec = OmegaConf.load(hydra / "config.yaml").train.get("eval_after")
    if not spec:
        raise RealIkeaError(f"{run}: the run has no train.eval_after to repeat")
    if collision:
        spec = OmegaConf.merge(spec, {"collision": collision})
    found = checkpoints(run)
    if not found:
        raise RealIkeaError(f"{run}: no model_<iteration>.pt checkpoint")
    previous = run / EVAL_FILE
    seconds = None
    if previous.is_file():
        seconds = json.loads(previous.read_text()).get("train_seconds")
    run_overrides = [*OmegaConf.load(hydra / "overrides.yaml"), *run_scene(hydra)]
    split = rerun_split(hydra)
    try:
        check_eval_spec(spec, run_overrides, split)
    except RealIkeaError as err:
        raise RealIkeaError(f"{run}: {err}") from err
    return run, spec, found[-1][1], run_overrides, seconds, split
