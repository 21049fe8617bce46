"""`realikea eval sweep RUN_DIR`: every checkpoint of a run under the three resistance modes.

The run's asset category and collision source are used unless the command line sets them. A
sweep selects a checkpoint, so it runs on the validation draw: the train parts (`asset.split=
train`) under `env.seed=2000` unless the command line sets them, and refuses the test parts
(`asset.split=test` or `all`): what the test draw reports must not have chosen the policy.

The appendix's policy selection: success and return against iteration per mode, and the most
robust checkpoint (highest success averaged over the modes; ties broken by the smaller spread
across modes, then by the mean return), with Wilson's interval on that mean (the modes' episodes
pooled): neighbouring checkpoints whose intervals overlap are not told apart by the sweep.
One env pool per mode serves all checkpoints, so every checkpoint meets the same configurations
and poses. Each (checkpoint, mode) result is appended to RUN/sweep/results.jsonl as it comes, with
the overrides that produced it: a stopped sweep rerun with the same overrides evaluates only what
is missing (about 30 s a checkpoint and mode at 50 episodes on one core).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

from realikea.assets.split import with_default_split
from realikea.config import load_config, override_key, overrides_set
from realikea.errors import RealIkeaError
from realikea.eval.protocol import run_episodes
from realikea.eval.setup import effective_config
from realikea.eval.stats import wilson
from realikea.eval.table import to_csv
from realikea.files import atomic_path, atomic_write_text, repo_path, shown_path
from realikea.markdown import table
from realikea.pool.env_pool import EnvPool
from realikea.sim.resistance import MODES
from realikea.tasks.randomization import two_phase_switch

RESULTS = "results.jsonl"  # one line per (checkpoint, mode) evaluated, for resuming
# the validation draw's seed: neither a training draw's (env.seed + i, small) nor the test
# draw's (1000) every evaluation command of the experiments uses
VALIDATION_SEED = 2000


def validation_overrides(overrides: list[str]) -> list[str]:
    """`overrides` on the validation draw (train parts, VALIDATION_SEED) unless they name the
    split or seed; refused if they name the test parts."""
    asked = with_default_split(overrides, "train")
    split = next(o.split("=", 1)[1] for o in reversed(asked) if override_key(o) == "asset.split")
    if split != "train":
        raise RealIkeaError(
            f"asset.split={split}: a checkpoint sweep selects a policy, so it may not look at "
            "the test parts; sweep on the train parts (the default, with env.seed="
            f"{VALIDATION_SEED}) and report the chosen checkpoint on the test draw"
        )
    if not overrides_set(asked, "env.seed"):
        asked.append(f"env.seed={VALIDATION_SEED}")
    return asked


def checkpoint_iteration(name: str) -> int | None:
    """The iteration of a checkpoint file named `model_<it>.pt`, else None."""
    match = re.fullmatch(r"model_(\d+)\.pt", Path(name).name)
    return int(match.group(1)) if match else None


def checkpoints(run: Path) -> list[tuple[int, Path]]:
    """(iteration, path) of every `model_<it>.pt` in a run directory, by iteration."""
    found = []
    for path in run.glob("model_*.pt"):
        iteration = checkpoint_iteration(path.name)
        if iteration is not None:
            found.append((iteration, path))
    if not found:
        raise RealIkeaError(f"{run}: no checkpoints model_<iteration>.pt")
    return sorted(found)


def done_results(path: Path, overrides: list[str]) -> dict[tuple[int, str], tuple[float, float]]:
    """(iteration, mode) -> (success, mean return) already in the sweep's results file for the
    same overrides (a rerun with other overrides evaluates everything again)."""
    if not path.is_file():
        return {}
    records = (json.loads(line) for line in path.read_text().splitlines() if line.strip())
    return {
        (r["iteration"], r["mode"]): (r["success"], r["return"])
        for r in records
        if r["overrides"] == overrides
    }


def most_robust(rows: list[dict]) -> dict:
    """The row (one per checkpoint) with the best mean success, then spread, then return."""
    return max(rows, key=lambda r: (r["mean_success"], -r["success_spread"], r["mean_return"]))


def plot(rows: list[dict], best: dict, path: Path, switch: int | None = None) -> None:
    """Mean success and mean return against iteration, one line per mode plus their mean; the
    most robust checkpoint and, for a two-phase run, the switch to randomized poses marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    its = [r["iteration"] for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    for ax, key, label in (
        (axes[0], "success", "success rate"),
        (axes[1], "return", "mean return"),
    ):
        for mode in MODES:
            ax.plot(its, [r[f"{key}_{mode}"] for r in rows], marker=".", label=mode)
        ax.plot(its, [r[f"mean_{key}"] for r in rows], "k--", lw=1.5, label="mean of modes")
        ax.axvline(best["iteration"], color="grey", lw=0.8, ls=":")
        if switch is not None:
            ax.axvline(switch, color="C3", lw=0.8, ls="-.", label="randomized poses from here")
        ax.set_xlabel("training iteration")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].set_ylim(-0.02, 1.02)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"checkpoint sweep: most robust = iteration {best['iteration']}", fontsize=10)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=120, format="png")
    plt.close(fig)


def sweep_rows(found: list[tuple[int, Path]], results: dict) -> list[dict]:
    """A row per checkpoint: success and return per mode, their means and the success spread."""
    rows = []
    for iteration, _ in found:
        row = {"iteration": iteration}
        for mode in MODES:
            row[f"success_{mode}"], row[f"return_{mode}"] = results[iteration, mode]
        successes = [row[f"success_{m}"] for m in MODES]
        row["mean_success"] = float(np.mean(successes))
        row["success_spread"] = float(np.ptp(successes))
        row["mean_return"] = float(np.mean([row[f"return_{m}"] for m in MODES]))
        rows.append(row)
    return rows


def sweep_markdown(run: Path, cfg, rows: list[dict], best: dict) -> list[str]:
    """sweep.md's lines: what was evaluated, then a row per checkpoint, the most robust marked."""
    episodes = int(cfg.episodes)
    lines = [
        f"# Checkpoint sweep of {shown_path(run)}",
        "",
        f"{episodes} episodes per checkpoint and mode; asset={cfg.asset.category} "
        f"(kind {cfg.asset.kind}) "
        f"collision={cfg.collision.source}, split {cfg.asset.split}, scene {cfg.scene.name}, "
        f"dr={cfg.dr.mode}, env.seed={cfg.env.seed}. Mean S: over the modes, with Wilson's 95 % "
        f"interval on the {len(MODES) * episodes} episodes pooled.",
        "",
    ]
    cells = []
    for r in rows:
        mark = " **most robust**" if r is best else ""
        lo, hi = wilson(round(r["mean_success"] * len(MODES) * episodes), len(MODES) * episodes)
        cells.append([
            f"{r['iteration']}{mark}", *(f"{r[f'success_{m}']:.2f}" for m in MODES),
            f"{r['mean_success']:.2f} [{lo:.2f}, {hi:.2f}]", f"{r['mean_return']:.0f}",
        ])  # fmt: skip
    header = ["iteration", *(f"S {m}" for m in MODES), "mean S [95 %]", "mean return"]
    return lines + table(header, "r" * len(header), cells)


def run_sweep(run: Path, overrides: list[str]) -> int:
    """Evaluate every checkpoint of the training run `run`; write RUN/sweep/{sweep.csv, sweep.md,
    sweep.png}."""
    from realikea.policies.checkpoint import CheckpointPolicy, run_config  # torch, on use

    run, rest = repo_path(run), list(overrides)
    found = checkpoints(run)
    run_cfg = run_config(found[0][1])
    mine = {override_key(o).split(".")[0] for o in rest}
    inherited = []
    if "collision" not in mine:
        inherited.append(f"collision={run_cfg.collision.source}")
    if "asset" not in mine:
        asset = run_cfg.asset
        inherited.append(f"asset={asset.category}")
        inherited += [f"asset.{k}={asset[k]}" for k in ("part", "base", "kind") if asset.get(k)]
    asked = validation_overrides([*inherited, *rest])
    out = run / "sweep"
    out.mkdir(exist_ok=True)
    results = done_results(out / RESULTS, asked)
    for mode in MODES:
        cfg = load_config([*asked, f"resistance={mode}", "policy=checkpoint"], "eval")
        cfg = effective_config(cfg, run_cfg, rest)
        cfg.contacts.log = False
        episodes = int(cfg.episodes)
        cfg.env.num_envs = min(episodes, int(cfg.env.num_envs))
        todo = [(it, path) for it, path in found if (it, mode) not in results]
        if not todo:
            continue
        with EnvPool.from_config(cfg) as pool, (out / RESULTS).open("a") as log:
            for iteration, path in todo:
                print(f"{mode}: iteration {iteration}", flush=True)
                result = run_episodes(pool, CheckpointPolicy(path), episodes)
                success = result.summary()["success"]
                ret = float(np.mean([e.get("episode_return", 0.0) for e in result.episodes]))
                results[iteration, mode] = (success, ret)
                record = {"iteration": iteration, "mode": mode, "success": success}
                log.write(json.dumps(record | {"return": ret, "overrides": asked}) + "\n")
                log.flush()
    rows = sweep_rows(found, results)
    best = most_robust(rows)
    atomic_write_text(out / "sweep.csv", to_csv(rows))
    plot(rows, best, out / "sweep.png", two_phase_switch(run_cfg.get("dr")))
    lines = sweep_markdown(run, cfg, rows, best)
    atomic_write_text(out / "sweep.md", "\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"most robust checkpoint: {found[[i for i, _ in found].index(best['iteration'])][1]}")
    return 0
