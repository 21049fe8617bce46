"""The fidelity-ablation report: every finished run (a directory holding `.hydra/config.yaml`,
`eval.json` and `metrics.csv`) under the given roots, aggregated into report.md and plots
(`python experiments/fidelity_ablation/report.py`, whose help says what it writes)."""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path

import matplotlib
import numpy as np
from omegaconf import OmegaConf

from realikea.eval.commands import run_eval
from realikea.eval.stats import count, seed_interval, wilson
from realikea.eval.sweep import checkpoint_iteration
from realikea.eval.table import CONTACT_STATS
from realikea.files import atomic_write_text
from realikea.reports.multiplicity import Difference, holm_lines
from realikea.reports.phase_map import difference_grid_lines, differences, read_cells
from realikea.sim.resistance import MODES
from realikea.tasks.failure_modes import FAILURE_MODES
from realikea.tasks.outcome import OUTCOMES
from realikea.tasks.randomization import two_phase_switch
from realikea.training.metrics import read_metrics

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

DEFAULT_OUT = "experiments/fidelity_ablation"
# the report's CoACD − hull tables, (evaluation modes, None = every mode; measure): the family
# Holm's correction counts; success comes first, in its own table before the failure modes
TESTED = ((None, "success"), (["high"], "slip"), (["high"], "hook"), (["high"], "form closure"))
SUCCESS_WINDOW = 20  # iterations averaged for "training success reached 50 %" and the curves
# iterations per window of the plateau check (training success over the last window against
# the one before): a grid run should train until its success has plateaued
PLATEAU_WINDOW = 100
SEED_STYLES = ("-", "--", ":", "-.")
OUTCOME_COLOURS = {"fail": "tab:red", "partial": "tab:orange", "success": "tab:green"}
STRATEGY_COLOURS = {
    "pinch": "tab:blue",
    "hook": "tab:purple",
    "lever": "tab:olive",
    "front_pinch": "tab:cyan",
    "front_hook": "tab:pink",
    "none": "0.75",
}
# per-episode labels an eval.json counts as rates: (its field, the labels, the cell key their
# per-seed (count, episodes) go to)
LABEL_FIELDS = (
    ("failure_modes", FAILURE_MODES, "failure_runs"),
    ("strategies", tuple(STRATEGY_COLOURS), "strategy_runs"),
)
# the paper's form closure: a hook on a bar or lip, a lever on a knob (realikea/tasks/contacts.py)
FORM_CLOSURE = ("hook", "lever")


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
            raise SystemExit(f"{root}: no such directory of runs")
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
    iterations, reaches `level` (None if it never does)."""
    its, values = (np.asarray(x) for x in run["metrics"].get("/episode/success", ([], [])))
    for start in np.unique(its):
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


def variant(run: dict, presets: int, schedules: int = 1) -> str:
    """The collision source, with the gripper/contact preset and the training schedule when
    several are present (the paper's 1,500 iterations are not pooled with the grid's 900)."""
    tags = [f"{run['gripper']}, {run['contact']}"] if presets > 1 else []
    tags += [schedule(run)] if schedules > 1 else []
    return run["collision"] + (f" ({'; '.join(tags)})" if tags else "")


def ordered(values, order=()) -> list:
    present = set(values)
    return [v for v in order if v in present] + sorted(present - set(order))


def aggregate(runs: list[dict]) -> tuple[dict, dict]:
    """cell (variant, resistance, category) -> eval mode -> mean summary over seeds; and
    cell -> its runs."""
    presets = len({(r["gripper"], r["contact"]) for r in runs})
    schedules = len({schedule(r) for r in runs})
    by_cell = defaultdict(list)
    for run in runs:
        run["variant"] = variant(run, presets, schedules)
        by_cell[run["variant"], run["resistance"], run["category"]].append(run)
    cells = {}
    for key, members in by_cell.items():
        modes = {}
        for mode in ordered({m for r in members for m in r["eval"]["modes"]}, MODES):
            entries = [r["eval"]["modes"][mode] for r in members if mode in r["eval"]["modes"]]
            out = {o: float(np.mean([e[o] for e in entries])) for o in OUTCOMES}
            out["episodes"] = int(sum(e["episodes"] for e in entries))
            out["seeds"] = len(entries)
            # (successes, episodes) per seed: what the intervals are computed from
            out["runs"] = [(count(e["success"], e["episodes"]), e["episodes"]) for e in entries]
            # (episodes with that label, episodes) per seed, as "runs" for the success
            for field, labels, counts in LABEL_FIELDS:
                labelled = [e for e in entries if e.get(field)]
                if labelled:
                    out[counts] = {
                        label: [
                            (count(e[field].get(label, 0.0), e["episodes"]), e["episodes"])
                            for e in labelled
                        ]
                        for label in labels
                    }
                    out[field] = {
                        label: float(np.mean([k / n for k, n in runs]))
                        for label, runs in out[counts].items()
                    }
            for stat in CONTACT_STATS:
                values = [e.get("contacts", {}).get(stat) for e in entries]
                values = [v for v in values if v is not None]
                out[stat] = float(np.mean(values)) if values else None
            modes[mode] = out
        cells[key] = modes
    return cells, by_cell


def _fmt(value, digits=2) -> str:
    return "–" if value is None else f"{value:.{digits}f}"


def outcome_tables(cells: dict, variants, resistances, categories, modes) -> list[str]:
    """Fail / Partial / Success per cell and evaluation mode, mean over seeds."""
    lines = [
        "## Fail / Partial / Success per cell",
        "",
        "| collision | trained on | category | seeds | "
        + " | ".join(f"{m} F | P | S" for m in modes)
        + " |",
        "|---|---|---|---:|" + "---:|---:|---:|" * len(modes),
    ]
    for v, res, category in present_cells(cells, variants, resistances, categories):
        cell = cells[v, res, category]
        seeds = max(c["seeds"] for c in cell.values())
        values = []
        for m in modes:
            c = cell.get(m)
            values += [_fmt(c[o]) for o in OUTCOMES] if c else ["", "", ""]
        lines.append(f"| {v} | {res} | {category} | {seeds} | " + " | ".join(values) + " |")
    return lines


def present_cells(cells: dict, variants, resistances, categories) -> list[tuple[str, str, str]]:
    """(variant, training resistance, category) of every cell present, in report order."""
    order = [(v, r, c) for v in variants for r in resistances for c in categories]
    return [key for key in order if key in cells]


def rate_interval(runs: list[tuple[int, int]]) -> tuple[float, float, float]:
    """(mean, low, high) of a cell's success: Wilson's interval for one run, else the two-level
    bootstrap over seeds and episodes (realikea/eval/stats.py)."""
    if len(runs) == 1:
        ((k, n),) = runs
        return (k / n, *wilson(k, n))
    return seed_interval(runs)


def interval_lines(
    cells: dict, by_cell: dict, variants, resistances, categories, modes
) -> list[str]:
    """Success per cell with its 95 % interval, the number of seeds and how many of them
    learned to open in training."""
    lines = [
        "## Success with 95 % intervals",
        "",
        "Mean success over seeds [95 % interval]: with one seed, Wilson's interval over its "
        "episodes; with several, a percentile bootstrap that redraws seeds, then each seed's "
        "episodes (`realikea.eval.stats.seed_interval`), so seed-to-seed spread counts. "
        "`learned`: the seeds whose training success reached 50 % (`to 50 %` below); a run "
        "that never finds an opening pulls its cell's mean down whatever the geometry.",
        "",
        "| collision | trained on | category | seeds | learned | " + " | ".join(modes) + " |",
        "|---|---|---|---:|---:|" + "---|" * len(modes),
    ]
    for v, res, category in present_cells(cells, variants, resistances, categories):
        cell = cells[v, res, category]
        values = []
        for m in modes:
            if m not in cell:
                values.append("")
                continue
            mean, lo, hi = rate_interval(cell[m]["runs"])
            values.append(f"{mean:.2f} [{lo:.2f}, {hi:.2f}]")
        seeds = max(c["seeds"] for c in cell.values())
        learned = sum(iterations_to_success(r) is not None for r in by_cell[v, res, category])
        row = f"| {v} | {res} | {category} | {seeds} | {learned} | "
        lines.append(row + " | ".join(values) + " |")
    return lines


def measured_runs(entry: dict, measure: str) -> list[tuple[int, int]] | None:
    """(count, episodes) per seed of `measure` in one cell and mode: "success", a failure mode,
    a strategy label or "form closure" (hook or lever). None when the cell's evaluations carry
    no such labels."""
    if measure == "success":
        return entry["runs"]
    if measure in FAILURE_MODES:
        return entry.get("failure_runs", {}).get(measure)
    strategy_runs = entry.get("strategy_runs", {})
    if measure == "form closure":  # the labels are exclusive per episode: their counts add
        if not all(label in strategy_runs for label in FORM_CLOSURE):
            return None
        per_seed = zip(*(strategy_runs[label] for label in FORM_CLOSURE), strict=True)
        return [(sum(k for k, _ in seed), seed[0][1]) for seed in per_seed]
    return strategy_runs.get(measure)


def paired_differences(
    cells: dict, variants, resistances, categories, modes, measure: str = "success"
) -> list[tuple[tuple[str, str, str, str], Difference]]:
    """Every CoACD − hull (of the same preset) comparison of `measure` (success, the rate of a
    failure mode or of a strategy label) the cells allow, per training resistance, category and
    evaluation mode: ((coacd variant, resistance, category, mode), difference)."""
    pairs = [(v, "hull" + v[5:]) for v in variants if v.startswith("coacd")]
    out = []
    for coacd, hull in pairs:
        for res in resistances:
            for category in categories:
                a, b = cells.get((coacd, res, category), {}), cells.get((hull, res, category), {})
                for m in modes:
                    if m not in a or m not in b:
                        continue
                    runs_a, runs_b = measured_runs(a[m], measure), measured_runs(b[m], measure)
                    if runs_a and runs_b:
                        label = f"{measure}: {coacd} − hull, trained in {res}, {category}, in {m}"
                        out.append(((coacd, res, category, m), Difference(label, runs_a, runs_b)))
    return out


def difference_lines(
    cells: dict, variants, resistances, categories, modes, measure: str = "success"
) -> list[str]:
    """CoACD minus hull of `measure` (`paired_differences`), with its interval and whether it
    excludes zero."""
    title = "CoACD − hull" if measure == "success" else f"{measure.capitalize()} rate: CoACD − hull"
    lines = [
        f"## {title}",
        "",
        f"Difference of the mean {measure} rate [95 % interval] (Newcombe's with one seed a "
        "side, else the two-level bootstrap); a difference is named only where the interval "
        "excludes zero.",
        "",
        "| CoACD | trained on | category | evaluated in | CoACD | hull | CoACD − hull [95 %] | |",
        "|---|---|---|---|---:|---:|---|---|",
    ]
    for (coacd, res, category, m), diff in paired_differences(
        cells, variants, resistances, categories, modes, measure
    ):
        d, lo, hi = diff.interval()
        verdict = "significant" if lo > 0 or hi < 0 else "not significant"
        mean_a, mean_b = (np.mean([k / n for k, n in r]) for r in (diff.a, diff.b))
        lines.append(
            f"| {coacd} | {res} | {category} | {m} | {mean_a:.2f} | {mean_b:.2f} | "
            f"{d:+.2f} [{lo:+.2f}, {hi:+.2f}] | {verdict} |"
        )
    return lines


def failure_lines(cells: dict, variants, resistances, categories, mode: str = "high") -> list[str]:
    """Failure modes per cell under one evaluation mode (fractions of all its episodes)."""
    lines = [
        f"## Failure modes (evaluated in {mode})",
        "",
        "Fraction of all episodes that failed (fail or partial) in each mode "
        "(realikea/tasks/failure_modes.py; validated in "
        "experiments/fidelity_ablation/failure_modes.md), mean over seeds [95 % interval, as "
        "for the success]; the means add up to 1 − success.",
        "",
        "| collision | trained on | category | " + " | ".join(FAILURE_MODES) + " |",
        "|---|---|---|" + "---|" * len(FAILURE_MODES),
    ]
    for v, res, category in present_cells(cells, variants, resistances, categories):
        entry = cells[v, res, category].get(mode, {})
        if "failure_runs" in entry:
            values = []
            for f in FAILURE_MODES:
                mean, lo, hi = rate_interval(entry["failure_runs"][f])
                values.append(f"{mean:.2f} [{lo:.2f}, {hi:.2f}]")
            lines.append(f"| {v} | {res} | {category} | " + " | ".join(values) + " |")
    return lines


def strategy_totals(cells: dict, variants, categories) -> dict:
    """(variant, category or 'all') -> mean strategy fractions over resistances and eval modes."""
    totals = {}
    for v in variants:
        for category in [*categories, "all"]:
            fractions = [
                m["strategies"]
                for (cv, _, cc), modes in cells.items()
                if cv == v and category in (cc, "all")
                for m in modes.values()
                if "strategies" in m
            ]
            if fractions:
                totals[v, category] = {
                    s: float(np.mean([f[s] for f in fractions])) for s in STRATEGY_COLOURS
                }
    return totals


def strategy_lines(cells, totals, variants, categories) -> list[str]:
    lines = [
        "## Strategies by collision source",
        "",
        "Fraction of evaluation episodes per classifier label (realikea/tasks/contacts.py), "
        "averaged over training resistances, evaluation modes and seeds; friction share and "
        "front share = mean share of the pull carried by friction and by contacts on the front "
        "off the part (`front_*` labels) in episodes that pulled.",
        "",
        "| collision | category | "
        + " | ".join(STRATEGY_COLOURS)
        + " | friction share | front share |",
        "|---|---|" + "---:|" * (len(STRATEGY_COLOURS) + 2),
    ]

    def mean_stat(v, category, stat):
        values = [
            m[stat]
            for (cv, _, cc), modes in cells.items()
            if cv == v and category in (cc, "all")
            for m in modes.values()
            if m.get(stat) is not None
        ]
        return float(np.mean(values)) if values else None

    for v in variants:
        for category in [*categories, "all"]:
            if (v, category) not in totals:
                continue
            fractions = " | ".join(_fmt(totals[v, category][s]) for s in STRATEGY_COLOURS)
            friction = _fmt(mean_stat(v, category, "friction_share"))
            front = _fmt(mean_stat(v, category, "front_share"))
            lines.append(f"| {v} | {category} | {fractions} | {friction} | {front} |")
    return lines


def per_run_lines(runs: list[dict], root: Path) -> list[str]:
    """One row per run: success under each evaluation mode, strategy fractions under its
    training resistance, and how soon training found a way to open."""
    lines = [
        "## Per run",
        "",
        "Success under each evaluation mode; strategy fractions under the run's training "
        "resistance; `form closure of S`: the share of its successful episodes there labelled "
        "`hook` or `lever`; `to 50 %`: the first iteration from which training success, "
        "averaged over the next 20 iterations, reaches 50 % (how soon the run found a way to "
        "open); `train S` and `train P`: training success and partial openings over the last "
        f"{PLATEAU_WINDOW} iterations, with their change from the {PLATEAU_WINDOW} before "
        "(a run still climbing has not plateaued).",
        "",
        "| run | "
        + " | ".join(f"{m} S" for m in MODES)
        + " | "
        + " | ".join(STRATEGY_COLOURS)
        + " | form closure of S | to 50 % | train S | change | train P | change |",
        "|---|" + "---:|" * (len(MODES) + len(STRATEGY_COLOURS) + 6),
    ]
    for run in runs:
        modes = run["eval"]["modes"]
        success = [_fmt(modes[m]["success"]) if m in modes else "" for m in MODES]
        trained = modes.get(run["resistance"]) or {}
        fractions = [_fmt((trained.get("strategies") or {}).get(s)) for s in STRATEGY_COLOURS]
        won = trained.get("success_strategies")
        has_wins = won and trained["success"] > 0
        closure = _fmt(sum(won[label] for label in FORM_CLOSURE)) if has_wins else "–"
        reached = iterations_to_success(run)
        row = [*success, *fractions, closure, "–" if reached is None else str(reached)]
        for tag in ("/episode/success", "/episode/partial"):
            mean, change = last_windows(run, tag)
            row += [_fmt(mean), "–" if change is None else f"{change:+.2f}"]
        lines.append(f"| {_rel(run['dir'], root)} | " + " | ".join(row) + " |")
    return lines


def compute_lines(runs: list[dict], root: Path) -> list[str]:
    lines = [
        "## Compute",
        "",
        "Iterations behind the evaluated checkpoint; the last launch's iterations, training "
        "minutes and seconds per iteration (a resumed run's earlier launches are in its wall "
        "time only); eval minutes from eval.json; wall: every launch of the run, training and "
        "evaluation, beside whatever else ran.",
        "",
        "| run | iterations | envs | last launch: its | train (min) | s / iteration | eval (min) "
        "| wall (min) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    total = 0.0
    for run in runs:
        seconds = train_seconds(run)
        eval_seconds = run["eval"].get("eval_seconds", 0.0)
        total += sum(run["wall"]) if run["wall"] else (seconds or 0.0) + eval_seconds
        per_it = seconds / run["launch_iterations"] if seconds else None
        lines.append(
            f"| {_rel(run['dir'], root)} | {run['iterations']} | {run['num_envs']} | "
            f"{run['launch_iterations']} | {_fmt(seconds / 60 if seconds else None, 1)} | "
            f"{_fmt(per_it)} | {eval_seconds / 60:.1f} | "
            f"{_fmt(sum(run['wall']) / 60 if run['wall'] else None, 1)} |"
        )
    lines += ["", f"Total compute (sum over runs; wall time where recorded): {total / 3600:.2f} h."]
    return lines


def _rel(path: Path, root: Path) -> str:
    return os.path.relpath(Path(path).resolve(), Path(root).resolve())


def _save(fig, path: Path) -> None:
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_success(cells, variants, resistances, categories, modes, path: Path) -> None:
    """Grouped bars per category: x = (trained on, evaluated under), one bar per variant."""
    fig, axes = plt.subplots(len(categories), 1, figsize=(11, 2.8 * len(categories)), squeeze=False)
    groups = [(r, m) for r in resistances for m in modes]
    width = 0.8 / len(variants)
    for ax, category in zip(axes[:, 0], categories, strict=True):
        for i, v in enumerate(variants):
            heights = [
                cells.get((v, r, category), {}).get(m, {}).get("success", np.nan) for r, m in groups
            ]
            ax.bar(
                np.arange(len(groups)) + (i - (len(variants) - 1) / 2) * width,
                heights,
                width,
                label=v,
            )
        ax.set_xticks(np.arange(len(groups)), [f"{r}\n→ {m}" for r, m in groups], fontsize=8)
        ax.set(ylim=(0, 1.02), ylabel="success", title=category)
        ax.grid(axis="y", alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    axes[-1, 0].set_xlabel("trained on → evaluated under")
    _save(fig, path)


def plot_outcomes(cells, variants, resistances, categories, modes, path: Path) -> None:
    """Stacked Fail / Partial / Success bars per cell and evaluation mode."""
    fig, axes = plt.subplots(len(categories), 1, figsize=(11, 2.8 * len(categories)), squeeze=False)
    columns = [(v, r, m) for v in variants for r in resistances for m in modes]
    for ax, category in zip(axes[:, 0], categories, strict=True):
        bottom = np.zeros(len(columns))
        for o in OUTCOMES:
            heights = np.array(
                [cells.get((v, r, category), {}).get(m, {}).get(o, np.nan) for v, r, m in columns]
            )
            ax.bar(
                np.arange(len(columns)),
                heights,
                0.8,
                bottom=bottom,
                color=OUTCOME_COLOURS[o],
                label=o,
            )
            bottom = bottom + np.nan_to_num(heights)
        ax.set_xticks(np.arange(len(columns)), [f"{v}\n{r}→{m}" for v, r, m in columns], fontsize=6)
        ax.set(ylim=(0, 1.02), ylabel="fraction", title=category)
    axes[0, 0].legend(fontsize=8, loc="upper right")
    _save(fig, path)


def plot_strategies(totals, variants, categories, path: Path) -> None:
    """Stacked strategy fractions: one bar per collision source, a panel per category + all."""
    panels = [c for c in [*categories, "all"] if any((v, c) in totals for v in variants)]
    fig, axes = plt.subplots(
        1,
        len(panels),
        figsize=(1.1 * len(variants) * len(panels) + 1, 4.0),
        squeeze=False,
        sharey=True,
    )
    for ax, category in zip(axes[0], panels, strict=True):
        bottom = np.zeros(len(variants))
        for s, colour in STRATEGY_COLOURS.items():
            heights = np.array([totals.get((v, category), {}).get(s, 0.0) for v in variants])
            ax.bar(np.arange(len(variants)), heights, 0.7, bottom=bottom, color=colour, label=s)
            bottom += heights
        labels = [v.replace(" (", "\n(").replace(", ", ",\n") for v in variants]
        ax.set_xticks(np.arange(len(variants)), labels, fontsize=7)
        ax.set(ylim=(0, 1.02), title=category)
    axes[0, 0].set_ylabel("fraction of episodes")
    axes[0, -1].legend(fontsize=8, loc="upper right")
    _save(fig, path)


def plot_learning_curves(by_cell, variants, resistances, categories, path: Path) -> None:
    """Training success fraction against iteration, averaged over the `window` iterations of
    `iterations_to_success` (raw per-iteration values swing 0 to 1): a panel per (category,
    training resistance), a colour per collision source, a line style per seed."""
    fig, axes = plt.subplots(
        len(categories), len(resistances),
        figsize=(max(6, 4 * len(resistances)), 2.8 * len(categories)),
        squeeze=False, sharey=True,
    )  # fmt: skip
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for row, category in enumerate(categories):
        for col, res in enumerate(resistances):
            ax = axes[row, col]
            for i, v in enumerate(variants):
                for k, run in enumerate(sorted(by_cell.get((v, res, category), []), key=_seed)):
                    its, values = run["metrics"].get("/episode/success", ([], []))
                    its, values = trailing_mean(its, values, SUCCESS_WINDOW)
                    style = SEED_STYLES[k % len(SEED_STYLES)]
                    ax.plot(
                        its, values, color=colours[i % len(colours)], ls=style, lw=1.0,
                        label=f"{v}, s{run['seed']}",
                    )  # fmt: skip
            ax.set(title=f"{category}, trained on {res}", ylim=(-0.02, 1.02))
            ax.grid(alpha=0.3)
            if row == len(categories) - 1:
                ax.set_xlabel("iteration")
            if col == 0:
                ax.set_ylabel("training success")
    legend = {}  # label -> line, over every panel: each source and seed once
    for ax in axes.flat:
        handles, labels = ax.get_legend_handles_labels()
        legend.update(zip(labels, handles, strict=True))
    axes[0, -1].legend(
        legend.values(), legend.keys(), fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1)
    )
    _save(fig, path)


def _seed(run: dict) -> int:
    return run["seed"]


def trailing_mean(its, values, window: int) -> tuple[np.ndarray, np.ndarray]:
    """The mean of `values` over each `window` consecutive iterations, at the window's last
    iteration (nothing before a full window)."""
    its, values = np.asarray(its), np.asarray(values, float)
    if len(values) < window:
        return its[:0], values[:0]
    order = np.argsort(its, kind="stable")
    its, values = its[order], values[order]
    means = np.convolve(values, np.ones(window) / window, mode="valid")
    return its[window - 1 :], means


def record_videos(runs: list[dict], episodes: int) -> None:
    """`realikea eval <the run's eval command> video=true episodes=N` under its training
    resistance, with the checkpoint kept in the run's directory (the command names where it was
    trained): the first of the N episodes with each strategy label. A run whose videos/ already
    holds strips is skipped (delete the folder to record it again), so a stopped recording
    resumes."""
    for run in runs:
        if run["strips"]:
            continue
        entry = run["eval"]["modes"].get(run["resistance"]) or next(
            iter(run["eval"]["modes"].values())
        )
        checkpoint = run["dir"] / run["eval"]["checkpoint"]
        overrides = [
            o
            for o in entry["command"].split()[2:]
            if not o.startswith(("episodes=", "policy.path="))
        ] + [f"policy.path={checkpoint.resolve()}"]
        stem = run["dir"] / "videos" / "eval.mp4"
        for old in stem.parent.glob("eval_*"):  # labels of an earlier recording
            old.unlink()
        args = [*overrides, f"episodes={episodes}", "video=true", f"video_path={stem}"]
        run_eval(argparse.Namespace(overrides=[*args, "env.num_workers=0"]))
        run["strips"] = sorted(stem.parent.glob("*.png"))


def typical_strategy(run: dict) -> str | None:
    """The most frequent strategy label of the run's evaluation under its training resistance."""
    entry = run["eval"]["modes"].get(run["resistance"]) or {}
    strategies = entry.get("strategies") or {}
    return max(strategies, key=strategies.get) if strategies else None


def frame_lines(runs: list[dict], out: Path) -> list[str]:
    """Per run, the four-frame strip of its typical strategy inline and its other strips named."""
    lines = [
        "## Frames of the typical strategy per run",
        "",
        "Four frames (the scene above a close-up of the handle) of one recorded evaluation "
        "episode under the run's training resistance with the run's most frequent strategy "
        "label: the first success with that label, else its first episode. Strips of the other "
        "labels seen in the recorded episodes are linked. The MP4 beside each strip is "
        "git-ignored and written again by `--record-videos`.",
        "",
    ]
    recorded = [run for run in runs if run["strips"]]
    for run in recorded:
        cell = f"{run['variant']} / {run['category']} / trained on {run['resistance']}"
        cell += f" / s{run['seed']}"
        typical = typical_strategy(run)
        by_label = {s.stem.removeprefix("eval_").rsplit("_", 1)[0]: s for s in run["strips"]}
        shown = by_label.get(typical)
        others = [f"[{label}]({_rel(s, out)})" for label, s in by_label.items() if s != shown]
        lines.append(f"### {cell}")
        lines.append("")
        if shown is not None:
            video = _rel(shown.with_suffix(".mp4"), out)
            outcome = shown.stem.rsplit("_", 1)[-1]
            lines += [f"Typical: `{typical}`, an episode ending in {outcome} ([MP4]({video})).", ""]
            lines += [f"![{cell} {typical}]({_rel(shown, out)})", ""]
        else:
            lines += [f"Typical: `{typical}`, not among the recorded episodes.", ""]
        if others:
            lines += ["Other labels: " + ", ".join(others) + ".", ""]
    if not recorded:
        lines.append(
            "None recorded: `python experiments/fidelity_ablation/report.py --record-videos` "
            "writes one MP4 and strip per strategy label into each RUN/videos/."
        )
    return lines


def phase_map_lines(maps: Sequence[Path], out: Path) -> list[str]:
    """Markdown: each phase map (a directory `phase_map.py` wrote: cells.jsonl, phase_map.md,
    phase_map.png) with what it maps, its heat maps and its CoACD − hull differences."""
    missing = [
        m / name
        for m in maps
        for name in ("cells.jsonl", "phase_map.md", "phase_map.png")
        if not (m / name).is_file()
    ]
    if missing:
        raise SystemExit(
            f"not a phase map (phase_map.py writes these): {', '.join(map(str, missing))}"
        )
    mapped = {folder: read_cells(folder / "cells.jsonl") for folder in maps}
    empty = [str(folder / "cells.jsonl") for folder, cells in mapped.items() if not cells]
    if empty:
        raise SystemExit(f"phase map without cells: {', '.join(empty)}")
    lines = ["## Friction-trap phase maps", ""] if maps else []
    for folder, cells in mapped.items():
        records = list(cells.values())
        policies = ", ".join(dict.fromkeys(r["policy"] for r in records))
        cones = ", ".join(dict.fromkeys(r["cone"] for r in records))
        episodes = "/".join(map(str, sorted({r["episodes"] for r in records})))
        splits = "/".join(sorted({r.get("split", "all") for r in records}))
        resistances = "/".join(sorted({r["resistance"] for r in records}))
        table = _rel(folder / "phase_map.md", out)
        checkpoints = {
            r["policy"]: token.removeprefix("policy.path=")
            for r in records
            for token in r.get("command", "").split()
            if token.startswith("policy.path=")
        }
        lines += [
            f"### {_rel(folder, out)}",
            "",
            f"Policies {policies}; {cones} cones; {len(records)} cells of {episodes} episodes, "
            f"{splits} parts, resistance {resistances}. "
            f"Every cell's success and slip ratio: [phase_map.md]({table}).",
            "",
            *[f"- {policy}: `{path}`" for policy, path in checkpoints.items()],
            "",
            f"![{folder.name}]({_rel(folder / 'phase_map.png', out)})",
            "",
            *difference_grid_lines(cells, "coacd", "hull"),
        ]
        family = list(differences(cells, "coacd", "hull").values())
        if family:
            lines += ["", *holm_lines(family, "Every cell of this map at once (Holm)", "####")]
    return lines


def report(roots: list[Path], out: Path, phase_maps: Sequence[Path] = ()) -> Path:
    runs = find_runs(roots)
    unfinished = unfinished_runs(roots)
    for run in unfinished:
        print(f"not in the report (no eval.json yet): {run}", file=sys.stderr)
    if not runs:
        raise SystemExit(f"no finished runs (eval.json + .hydra/config.yaml) under {roots}")
    maps = phase_map_lines(phase_maps, out)  # checked before anything is written
    cells, by_cell = aggregate(runs)
    variants = ordered({k[0] for k in cells}, ("coacd", "hull"))
    resistances = ordered({k[1] for k in cells}, MODES)
    categories = ordered({k[2] for k in cells}, ("knob", "finger_pull", "two_point"))
    modes = ordered({m for c in cells.values() for m in c}, MODES)
    totals = strategy_totals(cells, variants, categories)
    axes = (cells, variants, resistances, categories)
    out.mkdir(parents=True, exist_ok=True)
    plot_success(cells, variants, resistances, categories, modes, out / "success.png")
    plot_outcomes(cells, variants, resistances, categories, modes, out / "outcomes.png")
    plot_strategies(totals, variants, categories, out / "strategies.png")
    plot_learning_curves(by_cell, variants, resistances, categories, out / "learning_curves.png")
    presets = sorted({(r["gripper"], r["contact"]) for r in runs})
    episodes = sorted({r["eval"]["episodes"] for r in runs})
    splits = sorted({r["eval"].get("split", "all") for r in runs})
    scenes = sorted({r["scene"] for r in runs})
    seeds = sorted({r["seed"] for r in runs})
    root = roots[0] if len(roots) == 1 else Path.cwd()
    lines = [
        "# Fidelity ablation",
        "",
        f"{len(runs)} runs from {', '.join(str(r) for r in roots)}; scene "
        f"{', '.join(scenes)}; evaluation split {'/'.join(splits)}; "
        f"gripper/contact presets: {', '.join('/'.join(p) for p in presets)}; "
        f"training seeds {', '.join(map(str, seeds))}; "
        f"{'/'.join(map(str, episodes))} evaluation episodes per run and mode "
        "(`train.eval_after`, the last checkpoint).",
        "",
        "![success](success.png)",
        "",
        *interval_lines(cells, by_cell, variants, resistances, categories, modes),
        "",
        *difference_lines(cells, variants, resistances, categories, modes),
        "",
        *failure_lines(cells, variants, resistances, categories),
        "",
        *[
            line
            for tested_modes, measure in TESTED[1:]
            for line in [*difference_lines(*axes, tested_modes, measure), ""]
        ],
        *holm_lines(
            [
                diff
                for tested_modes, measure in TESTED
                for _, diff in paired_differences(*axes, tested_modes or modes, measure)
            ],
            "Every difference at once (Holm)",
        ),
        "",
        *outcome_tables(cells, variants, resistances, categories, modes),
        "",
        "![outcomes](outcomes.png)",
        "",
        *strategy_lines(cells, totals, variants, categories),
        "",
        "![strategies](strategies.png)",
        "",
        "## Learning curves",
        "",
        "![learning curves](learning_curves.png)",
        "",
        *per_run_lines(runs, root),
        "",
        *compute_lines(runs, root),
    ]
    if unfinished:
        lines += [
            "",
            "Not counted (no eval.json yet): " + ", ".join(_rel(r, root) for r in unfinished),
        ]
    lines += ["", *maps, "", *frame_lines(runs, out)]
    path = out / "report.md"
    atomic_write_text(path, "\n".join(lines) + "\n")
    return path
