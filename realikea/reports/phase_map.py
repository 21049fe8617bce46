"""The friction-trap phase map: a policy's success and slip over grip force per jaw x pad friction
x friction cone, on the held-out drawers of one category in high resistance, with the analytic
boundary of a pinch, 2 mu F = the pull the drawer needs.

`evaluate_phase_map` runs `realikea eval` once per cell (the Franka Hand with
`gripper.grasp_force` and `gripper.pad_friction` set, `contact=<cone>`) and appends the cell's
JSON line to a results file as it goes, so an interrupted map continues where it stopped;
`phase_table` and `plot_phase_map` read that file.
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from realikea.assets.catalog import CATEGORIES, effective_split
from realikea.errors import RealIkeaError
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.stats import count
from realikea.files import shown_path
from realikea.markdown import table
from realikea.policies.registry import POLICIES
from realikea.reports.multiplicity import Difference
from realikea.sim.resistance import mode

# the axes' default values; their sources are in experiments/fidelity_ablation/phase_map_axes.md
FORCES = (5.0, 10.0, 20.0, 40.0, 70.0)  # N per jaw
FRICTIONS = (0.3, 0.5, 0.7, 1.0)  # pad on the part
CONES = ("elliptic", "pyramidal")
MAX_FORCE = 300.0  # N per jaw: beyond any parallel gripper's datasheet (Robotiq 2F-85: 235 N)
MAX_FRICTION = 2.0  # beyond any dry pad on a hard surface
RESISTANCE = "high"


@dataclass(frozen=True)
class MapPolicy:
    """A policy of the map: a label and the `realikea eval` overrides that select it."""

    label: str
    overrides: tuple[str, ...]


def map_policy(spec: str) -> MapPolicy:
    """`heuristic_pull` (a scripted policy's name) or `LABEL=CHECKPOINT.pt`."""
    label, sep, path = spec.partition("=")
    if sep:
        if not Path(path).is_file():
            raise RealIkeaError(f"policy {spec!r}: checkpoint {path} not found")
        # relative to the repository when inside it (policy.path's base), so cells.jsonl's
        # commands run from any checkout
        shown = shown_path(Path(path).resolve())
        return MapPolicy(label, ("policy=checkpoint", f"policy.path={shown}"))
    if spec not in POLICIES or spec in ("checkpoint", "teleop", "replay"):
        scripted = [p for p in POLICIES if p not in ("checkpoint", "teleop", "replay")]
        raise RealIkeaError(
            f"policy {spec!r}: use a scripted policy ({', '.join(scripted)}) or LABEL=CHECKPOINT"
        )
    return MapPolicy(spec, (f"policy={spec}",))


def check_axes(forces, frictions, cones, categories) -> None:
    """Refuse values outside physical range before anything runs or is written."""
    for force in forces:
        if not 0 < force <= MAX_FORCE:
            raise RealIkeaError(f"grip force {force} N: use 0 < F <= {MAX_FORCE:g} N per jaw")
    for mu in frictions:
        if not 0 < mu <= MAX_FRICTION:
            raise RealIkeaError(f"pad friction {mu}: use 0 < mu <= {MAX_FRICTION:g}")
    for cone in cones:
        if cone not in CONES:
            raise RealIkeaError(f"friction cone {cone!r}: use {' or '.join(CONES)}")
    for category in categories:
        if category not in CATEGORIES:
            raise RealIkeaError(f"category {category!r}: use {', '.join(CATEGORIES)}")


def required_pull(resistance: str = RESISTANCE) -> float:
    """N a drawer needs at its handle to break away in `resistance` (its joint's friction loss;
    realikea/conf/resistance)."""
    return mode(resistance).frictionloss


def cell_overrides(
    policy: MapPolicy, category, force, friction, cone, episodes, seed, extra=()
) -> list[str]:
    """`realikea eval` overrides of one cell: test parts, drawers, randomized poses, high;
    then `extra`."""
    return [
        *policy.overrides, f"asset={category}", "asset.kind=drawer", "asset.split=test",
        f"resistance={RESISTANCE}", "gripper=franka_hand", f"gripper.grasp_force={force:g}",
        f"gripper.pad_friction={friction:g}", f"contact={cone}", "dr=randomized",
        f"episodes={episodes}", f"env.seed={seed}", *extra,
    ]  # fmt: skip


def _key(record: dict) -> tuple:
    return (
        record["policy"], record["category"], record["cone"],
        float(record["force"]), float(record["friction"]),
    )  # fmt: skip


def read_cells(results: Path) -> dict[tuple, dict]:
    """(policy, category, cone, force, friction) -> the cell's record (JSON lines)."""
    if not Path(results).is_file():
        return {}
    lines = Path(results).read_text().splitlines()
    return {_key(r): r for r in (json.loads(line) for line in lines if line)}


def evaluate_phase_map(
    policies: list[MapPolicy],
    categories,
    results: Path,
    forces=FORCES,
    frictions=FRICTIONS,
    cones=CONES,
    episodes: int = 20,
    seed: int = 1000,
    extra: tuple[str, ...] = (),
) -> dict[tuple, dict]:
    """Evaluate every cell missing from `results`, appending one JSON line per cell; `extra`
    overrides go to every cell's evaluation."""
    check_axes(forces, frictions, cones, categories)
    if episodes < 1:
        raise RealIkeaError(f"episodes={episodes}: use 1 or more")
    results = Path(results)
    if results.exists() and not results.is_file():
        raise RealIkeaError(f"{results}: exists and is not a file")
    done = read_cells(results)
    todo = [
        (p, c, cone, float(f), float(mu))
        for p in policies for c in categories for cone in cones
        for f in forces for mu in frictions
        if (p.label, c, cone, float(f), float(mu)) not in done
    ]  # fmt: skip
    results.parent.mkdir(parents=True, exist_ok=True)
    for n, (policy, category, cone, force, mu) in enumerate(todo, 1):
        overrides = cell_overrides(policy, category, force, mu, cone, episodes, seed, extra)
        start = time.perf_counter()
        cfg, runner = eval_setup(overrides)
        result = evaluate(cfg, runner, progress=False)
        summary = result.summary()
        pulled = [e["peak_slip_ratio"] for e in result.episodes if e.get("pull_seconds", 0) > 0]
        record = {
            "policy": policy.label, "category": category, "cone": cone, "force": force,
            "friction": mu, "resistance": RESISTANCE, "split": effective_split(cfg.asset),
            "scene": str(cfg.scene.name), "collision": str(cfg.collision.source), "seed": seed,
            **summary,
            "slip_ratio": float(np.mean(pulled)) if pulled else None,
            "seconds": round(time.perf_counter() - start, 1),
            "command": "realikea eval " + " ".join(overrides),
        }  # fmt: skip
        with results.open("a") as f:
            f.write(json.dumps(record) + "\n")
        done[_key(record)] = record
        slip = "–" if record["slip_ratio"] is None else f"{record['slip_ratio']:.2f}"
        print(
            f"[{n}/{len(todo)}] {policy.label} {category} {cone} {force:g} N mu {mu:g}: "
            f"success {summary['success']:.2f}, slip ratio {slip}",
            flush=True,
        )
    return done


def _groups(cells: dict[tuple, dict]) -> list[tuple[str, str, str]]:
    """(policy, category, cone) in the order they first appear."""
    return list(dict.fromkeys(k[:3] for k in cells))


def _axes(cells, group) -> tuple[list[float], list[float]]:
    keys = [k for k in cells if k[:3] == group]
    return sorted({k[3] for k in keys}), sorted({k[4] for k in keys})


def boundary_force(mu: float, pull: float) -> float:
    """N per jaw at which a two-pad pinch carries `pull` by friction: 2 mu F = pull."""
    return pull / (2 * mu)


def _grid_table(title: str, forces, frictions, entry) -> list[str]:
    """Markdown: `title`, then force down (strongest first) x friction across, each cell
    `entry(force, mu)`."""
    header = ["grip per jaw", *(f"μ = {mu:g}" for mu in frictions)]
    rows = [[f"{force:g} N", *(entry(force, mu) for mu in frictions)] for force in reversed(forces)]
    return [title, "", *table(header, "l" + "r" * len(frictions), rows), ""]


def phase_table(cells: dict[tuple, dict], pull: float) -> list[str]:
    """Markdown: per policy, category and cone, success (slip ratio) over force x friction,
    each cell marked where the pinch's analytic capacity 2 mu F reaches the required pull."""
    lines = []
    for group in _groups(cells):
        policy, category, cone = group
        episodes = next(c["episodes"] for k, c in cells.items() if k[:3] == group)

        def entry(force, mu, group=group):
            c = cells.get((*group, force, mu))
            if c is None:
                return ""
            slip = "–" if c.get("slip_ratio") is None else f"{c['slip_ratio']:.2f}"
            mark = "*" if 2 * mu * force >= pull else ""
            return f"{c['success']:.2f} ({slip}){mark}"

        title = (
            f"**{policy}, {category}, {cone} cones** ({episodes} episodes a cell; success, "
            "slip ratio at the peak pull in brackets; * where 2 μ F ≥ the required pull)"
        )
        lines += _grid_table(title, *_axes(cells, group), entry)
    return lines


def differences(cells: dict[tuple, dict], first: str, second: str) -> dict[tuple, Difference]:
    """(category, cone, force, friction) -> `first` − `second` success in that cell, for every
    cell both policies were evaluated in: the family of the map's comparisons."""
    out = {}
    for (policy, category, cone, force, mu), a in cells.items():
        b = cells.get((second, category, cone, force, mu))
        if policy != first or b is None:
            continue
        label = f"{first} − {second}, {category}, {cone} cones, {force:g} N, μ {mu:g}"
        runs = [[(count(c["success"], c["episodes"]), c["episodes"])] for c in (a, b)]
        out[category, cone, force, mu] = Difference(label, *runs)
    return out


def difference_grid_lines(cells: dict[tuple, dict], first: str, second: str) -> list[str]:
    """Markdown: `first` − `second` success per category and cone over force x friction, with
    Newcombe's 95 % interval; ** where it excludes zero. Empty unless both policies are there."""
    compared = differences(cells, first, second)
    lines = []
    for policy, category, cone in _groups(cells):
        if policy != first or (second, category, cone) not in _groups(cells):
            continue

        def entry(force, mu, category=category, cone=cone):
            diff = compared.get((category, cone, force, mu))
            if diff is None:
                return ""
            d, low, high = diff.interval()
            text = f"{d:+.2f} [{low:+.2f}, {high:+.2f}]"
            return f"**{text}**" if low > 0 or high < 0 else text

        title = (
            f"**{first} − {second}, {category}, {cone} cones** (success difference [95 % "
            "interval, Newcombe]; **bold** where the interval excludes zero)"
        )
        lines += _grid_table(title, *_axes(cells, (first, category, cone)), entry)
    return lines


def plot_phase_map(cells: dict[tuple, dict], pull: float, path: Path) -> Path:
    """Heat maps of success and slip ratio per (policy, category, cone), force up, friction
    across, the boundary F = pull / (2 mu) drawn on each."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = _groups(cells)
    fig, axes = plt.subplots(
        len(groups), 2, figsize=(8.5, 2.9 * len(groups)), squeeze=False, constrained_layout=True
    )
    for row, group in zip(axes, groups, strict=True):
        forces, frictions = _axes(cells, group)
        panels = (("success", "success"), ("slip_ratio", "slip ratio"))
        for ax, (key, title) in zip(row, panels, strict=True):
            grid = np.full((len(forces), len(frictions)), np.nan)
            for i, force in enumerate(forces):
                for j, mu in enumerate(frictions):
                    value = cells.get((*group, force, mu), {}).get(key)
                    grid[i, j] = np.nan if value is None else value
            image = ax.imshow(grid, origin="lower", cmap="viridis", vmin=0, vmax=1, aspect="auto")
            for i in range(len(forces)):
                for j in range(len(frictions)):
                    if not math.isnan(grid[i, j]):
                        colour = "black" if grid[i, j] > 0.6 else "white"
                        ax.text(j, i, f"{grid[i, j]:.2f}", ha="center", va="center", color=colour)
            # the boundary in index coordinates: interpolate log-force between the rows
            mus = np.linspace(frictions[0], frictions[-1], 100)
            logf = np.log(boundary_force(mus, pull))
            top = len(forces) - 0.5
            rows = np.interp(logf, np.log(forces), np.arange(len(forces)), left=-0.5, right=top)
            cols = np.interp(mus, frictions, np.arange(len(frictions)))
            ax.plot(cols, rows, color="red", lw=2, label=f"2 μ F = {pull:g} N")
            ax.set_xticks(range(len(frictions)), [f"{m:g}" for m in frictions])
            ax.set_yticks(range(len(forces)), [f"{f:g}" for f in forces])
            ax.set_xlabel("pad friction μ")
            ax.set_ylabel("grip per jaw (N)")
            ax.set_title(f"{group[0]}, {group[1]}, {group[2]}: {title}", fontsize=9)
            fig.colorbar(image, ax=ax, shrink=0.8)
    # one legend above the panels: inside an axis it hid the top-left cell (70 N, the lowest mu)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside upper center", fontsize=8)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
