"""Cross-preset report of Table 2: where the friction trap appears and why (experiments/table2).

Reads every `<kind>/<gripper>_<contact>/table2.csv` written by `realikea eval table` (kinds:
drawer, door) and the grip sweep's, and writes `results/report.md` (tables only),
`results/figures.json` (every cell with its Wilson interval, the traps, the sweep: what the
README quotes by key) and `results/success.png`.
Usage: python experiments/table2/report.py
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from realikea.eval.stats import wilson  # noqa: E402
from realikea.files import atomic_write_text  # noqa: E402
from realikea.markdown import table  # noqa: E402
from realikea.sim.resistance import MODES  # noqa: E402
from realikea.sim.resistance import mode as resistance_mode

RESULTS = Path(__file__).resolve().parent / "results"
CATEGORIES = ("knob", "finger_pull", "two_point")
KINDS = ("drawer", "door")
FRICTION_BASED = ("heuristic_pull", "grasp_sampler")
TRAP_SMOOTH, TRAP_HIGH = 0.6, 0.1  # a trap: friction-based success >= 0.6 smooth, <= 0.1 high
MU = 1.0  # pad friction of both gripper presets (realikea/conf/gripper/*.yaml: pad_friction)


def load(pattern: str) -> dict[str, list[dict]]:
    """folder path under this directory ("door/franka_hand_elliptic") -> rows of its table2.csv
    (numbers as floats)."""
    presets = {}
    for path in sorted(RESULTS.glob(pattern), key=lambda p: (len(p.parent.name), p.parent.name)):
        with path.open() as f:
            rows = list(csv.DictReader(f))
        for row in rows:
            for key, value in row.items():
                with contextlib.suppress(ValueError):
                    row[key] = float(value)
        presets[path.parent.relative_to(RESULTS).as_posix()] = rows
    if not presets:
        raise SystemExit(f"no {pattern} under {RESULTS}: run experiments/table2/run.sh first")
    return presets


def cell(rows, policy, category, mode) -> dict | None:
    wanted = (policy, category, mode)
    return next((r for r in rows if (r["policy"], r["category"], r["resistance"]) == wanted), None)


def resistance_pull(name: str, speed: float = 0.1) -> float:
    """N the front's joint resists with at `speed` m/s: friction loss + damping x speed."""
    r = resistance_mode(name)
    return r.frictionloss + r.damping * speed


def plot(presets: dict[str, list[dict]], path: Path) -> None:
    """Success per policy and mode: one panel per preset x category."""
    names = list(presets)
    fig, axes = plt.subplots(
        len(names), len(CATEGORIES), figsize=(11, 2.4 * len(names)), squeeze=False
    )
    for i, name in enumerate(names):
        rows = presets[name]
        policies = list(dict.fromkeys(r["policy"] for r in rows))
        for j, category in enumerate(CATEGORIES):
            ax = axes[i][j]
            width = 0.8 / max(len(policies), 1)
            for k, policy in enumerate(policies):
                values = [
                    (c["success"] if (c := cell(rows, policy, category, m)) else 0.0) for m in MODES
                ]
                xs = [m + (k - (len(policies) - 1) / 2) * width for m in range(len(MODES))]
                ax.bar(xs, values, width, label=policy)
            ax.set_xticks(range(len(MODES)), MODES)
            ax.set_ylim(0, 1.05)
            ax.set_title(f"{name}: {category}", fontsize=9)
            if j == 0:
                ax.set_ylabel("success")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def trapped(rows, policy: str) -> tuple[list[str], list[str]]:
    """Success smooth -> normal -> high per category ('' if a mode is missing), and the
    categories where `policy` falls into the trap."""
    cells, trap = [], []
    for category in CATEGORIES:
        found = [cell(rows, policy, category, m) for m in MODES]
        if not all(found):
            cells.append("")
            continue
        s = [c["success"] for c in found]
        cells.append(" -> ".join(f"{v:.2f}" for v in s))
        if s[0] >= TRAP_SMOOTH and s[2] <= TRAP_HIGH:
            trap.append(category)
    return cells, trap


def figures(presets: dict, sweep: dict) -> dict:
    """Every cell (by `<kind>/<preset>/<policy>/<category>/<mode>`, the sweep's under
    `grip_sweep/<preset>_<F>N/...`) with its rate and Wilson interval and its pinch statistics;
    the traps; the front's resistance at 0.1 m/s per mode."""
    cells = {}
    for name, rows in {**presets, **sweep}.items():
        for r in rows:
            n = int(r["episodes"])
            lo, hi = wilson(round(r["success"] * n), n)
            key = f"{name}/{r['policy']}/{r['category']}/{r['resistance']}"
            cells[key] = {
                "episodes": n, "rate": [r["success"], lo, hi], "partial": r["partial"],
                "fail": r["fail"], "hook": r["strategy_hook"], "lever": r["strategy_lever"],
                "pinch": r["strategy_pinch"], "none": r["strategy_none"],
                "friction_share": r["friction_share"], "grip": r["grip_force"],
                "capacity": 2 * MU * r["grip_force"], "peak_pull": r["peak_pull"],
                "slip_ratio": r["peak_slip_ratio"], "normal_angle": r["normal_angle_deg"],
            }  # fmt: skip
            # no pulling phase: no pinch statistics (null in strict JSON, not NaN)
            cells[key] = {k: None if v != v else v for k, v in cells[key].items()}
    traps = {
        f"{name}/{policy}": trapped(rows, policy)[1]
        for name, rows in presets.items()
        for policy in FRICTION_BASED
    }
    pulls = {m: resistance_pull(m) for m in MODES}
    return {"cells": cells, "traps": traps, "resistance_pull_n": pulls}


def trap_section(presets: dict) -> list[str]:
    rows = []
    for name, found in presets.items():
        for policy in FRICTION_BASED:
            cells, trap = trapped(found, policy)
            if any(cells):
                rows.append([name, policy, *cells, ", ".join(trap) or "none"])
    header = ["kind/preset", "policy", "knob", "finger pull", "two-point", "trap on"]
    return ["## Does the friction trap appear?", "", *table(header, "llllll", rows)]


def form_closure_section(presets: dict, cells: dict) -> list[str]:
    """hook_oracle in high: each cell's rate with the Wilson interval of `figures()`."""
    rows = []
    for name in presets:
        for category in CATEGORIES:
            c = cells.get(f"{name}/hook_oracle/{category}/high")
            if c:
                rate, lo, hi = c["rate"]
                rows.append([
                    name, category, f"{rate:.2f} [{lo:.2f}, {hi:.2f}]", f"{c['partial']:.2f}",
                    f"{c['fail']:.2f}", f"{c['hook']:.2f}", f"{c['lever']:.2f}",
                    "–" if c["friction_share"] is None else f"{c['friction_share']:.2f}",
                ])  # fmt: skip
    header = ["kind/preset", "category", "success", "partial", "fail", "hook", "lever",
              "friction share"]  # fmt: skip
    return ["## Form closure: hook_oracle in high resistance", "",
            *table(header, "llrrrrrr", rows)]  # fmt: skip


def slip_section(presets: dict) -> list[str]:
    rows = []
    for name, found in presets.items():
        for policy in FRICTION_BASED:
            for category in ("knob", "finger_pull"):
                for mode in ("smooth", "high"):
                    c = cell(found, policy, category, mode)
                    if c and c["grip_force"] == c["grip_force"]:  # not NaN
                        rows.append([
                            name, policy, category, mode, f"{c['success']:.2f}",
                            f"{c['grip_force']:.1f}", f"{2 * MU * c['grip_force']:.1f}",
                            f"{c['peak_pull']:.1f}", f"{c['peak_slip_ratio']:.2f}",
                            f"{c['normal_angle_deg']:.0f}",
                        ])  # fmt: skip
    header = ["kind/preset", "policy", "category", "mode", "S", "grip (N)", "capacity (N)",
              "peak pull (N)", "slip ratio", "normal angle (deg)"]  # fmt: skip
    return ["## The slip condition, from the logged contact forces", "",
            *table(header, "llllrrrrrr", rows)]  # fmt: skip


def sweep_section(sweep: dict) -> list[str]:
    rows = []
    for name, found in sweep.items():
        cells = []
        for category in ("knob", "finger_pull"):
            modes = [cell(found, "heuristic_pull", category, m) for m in MODES]
            cells.append(" -> ".join(f"{c['success']:.2f}" for c in modes))
            ratio = modes[2]["peak_slip_ratio"]
            cells.append(f"{ratio:.2f}" if ratio == ratio else "no pull")
        force = name.rsplit("_", 1)[-1].removesuffix("N")
        rows.append([f"{force} N", *cells])
    header = ["grip per jaw", "knob", "slip ratio (high)", "finger pull", "slip ratio (high)"]
    return ["## Where the trap appears: the grip force", "", *table(header, "llrlr", rows)]


def main(argv: list[str] | None = None) -> None:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    presets = {}
    for kind in KINDS:
        presets.update(load(f"{kind}/*_*/table2.csv"))
    sweep = load("grip_sweep/*/table2.csv") if list(RESULTS.glob("grip_sweep/*/table2.csv")) else {}
    header = [
        "# Table 2 under every gripper x contact preset, on drawers and doors",
        "",
        "Command: `python experiments/table2/report.py` (after `bash experiments/table2/run.sh`); "
        "figures: [`figures.json`](figures.json); method and reading: "
        "[README.md](../README.md). Per kind and preset, the paper's layout, strategy labels "
        "and slip statistics per cell: "
        + ", ".join(f"[{n}]({n}/table2.md)" for n in presets)
        + ".",
        "",
        "![success](success.png)",
    ]
    found = figures(presets, sweep)
    sections = [header, trap_section(presets), form_closure_section(presets, found["cells"])]
    sections += [slip_section(presets)] + ([sweep_section(sweep)] if sweep else [])
    plot(presets, RESULTS / "success.png")
    data = json.dumps(found, indent=1, allow_nan=False)
    atomic_write_text(RESULTS / "figures.json", data + "\n")
    atomic_write_text(RESULTS / "report.md", "\n\n".join("\n".join(s) for s in sections) + "\n")
    print(f"wrote {RESULTS / 'report.md'} and figures.json")


if __name__ == "__main__":
    main()
