"""Cross-preset report of Table 2: where the friction trap appears and why (experiments/table2).

Reads every `<kind>/<gripper>_<contact>/table2.csv` written by `realikea eval table` (kinds:
drawer, door) and the grip sweep's, and writes `results/report.md` (findings computed from the CSVs)
and `results/success.png`.
Usage: python experiments/table2/report.py
"""

from __future__ import annotations

import contextlib
import csv
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from realikea.eval.stats import wilson  # noqa: E402
from realikea.sim.resistance import MODES  # noqa: E402
from realikea.sim.resistance import mode as resistance_mode

RESULTS = Path(__file__).resolve().parent / "results"
CATEGORIES = ("knob", "finger_pull", "two_point")
KINDS = ("drawer", "door")
FRICTION_BASED = ("heuristic_pull", "grasp_sampler")
TRAP_SMOOTH, TRAP_HIGH = 0.6, 0.1  # a trap: friction-based success >= 0.6 smooth, <= 0.1 high


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
    return next(
        (
            r
            for r in rows
            if r["policy"] == policy and r["category"] == category and r["resistance"] == mode
        ),
        None,
    )


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


def main() -> None:
    presets = {}
    for kind in KINDS:
        presets.update(load(f"{kind}/*_*/table2.csv"))
    first = next(iter(presets.values()))[0]
    lines = [
        "# Table 2 under every gripper x contact preset, on drawers and doors",
        "",
        "Command: `bash experiments/table2/run.sh` (runs `realikea eval table` per kind and "
        "preset, then this report: `python experiments/table2/report.py`). "
        f"Scene {first['scene']}, {first['split']} parts, {int(first['episodes'])} episodes a "
        f"cell, pose randomization on, {first['collision']} collision; drawers as in the paper, "
        "and doors. Per kind and preset, the tables (F/P/S in the paper's layout, strategy "
        "labels and slip statistics per cell): "
        + ", ".join(f"[{n}]({n}/table2.md)" for n in presets)
        + ".",
        "",
        "![success](success.png)",
        "",
        "## Does the friction trap appear?",
        "",
        f"Trap: a friction-based baseline succeeds in smooth (>= {TRAP_SMOOTH}) and collapses in "
        f"high (<= {TRAP_HIGH}). Success smooth -> normal -> high (at 50 episodes a rate's "
        "95 % interval spans up to +-14 points: `python -m realikea.eval.stats K/N`):",
        "",
        "| kind/preset | policy | knob | finger pull | two-point | trap on |",
        "|---|---|---|---|---|---|",
    ]
    for name, rows in presets.items():
        for policy in FRICTION_BASED:
            cells, trapped = [], []
            for category in CATEGORIES:
                found = [cell(rows, policy, category, m) for m in MODES]
                if not all(found):
                    cells.append("")
                    continue
                s = [c["success"] for c in found]
                cells.append(" -> ".join(f"{v:.2f}" for v in s))
                if s[0] >= TRAP_SMOOTH and s[2] <= TRAP_HIGH:
                    trapped.append(category)
            if any(cells):
                trap = ", ".join(trapped) or "none"
                lines.append(f"| {name} | {policy} | " + " | ".join(cells) + f" | {trap} |")
    lines += [
        "",
        "## Form closure: hook_oracle in high resistance",
        "",
        "Success with its Wilson 95 % interval; hook and lever: fractions of all episodes.",
        "",
        "| kind/preset | category | success | partial | fail | hook | lever | friction share |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, rows in presets.items():
        for category in CATEGORIES:
            c = cell(rows, "hook_oracle", category, "high")
            if c:
                n = int(c["episodes"])
                lo, hi = wilson(round(c["success"] * n), n)
                lines.append(
                    f"| {name} | {category} | {c['success']:.2f} [{lo:.2f}, {hi:.2f}] | "
                    f"{c['partial']:.2f} | "
                    f"{c['fail']:.2f} | {c['strategy_hook']:.2f} | {c['strategy_lever']:.2f} | "
                    f"{c['friction_share']:.2f} |"
                )
    pulls = ", ".join(f"{m} {resistance_pull(m):.0f} N" for m in MODES)
    lines += [
        "",
        "## The slip condition, from the logged contact forces",
        "",
        "A pinch holds while the pull the front needs stays below the friction the jaws can "
        "carry, about 2 mu F_grip (two pads) when the contact normals stand across the pull; "
        "on curved parts the normals tilt towards the pull (normal angle below 90 deg) and the "
        "jaws are pushed open instead. The front resists with its friction loss plus damping x "
        f"speed: at 0.1 m/s {pulls}. Per cell, means over the episodes with a pulling phase: "
        "grip = half the summed contact normal force, capacity = 2 mu grip, slip ratio = "
        "friction pull / (mu x summed normal force) at the peak pull (1 = sliding).",
        "",
        "| kind/preset | policy | category | mode | S | grip (N) | capacity (N) | peak pull (N) | "
        "slip ratio | normal angle (deg) |",
        "|---|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    mu = 1.0  # pad friction of both gripper presets (realikea/conf/gripper/*.yaml: pad_friction)
    for name, rows in presets.items():
        for policy in FRICTION_BASED:
            for category in ("knob", "finger_pull"):
                for mode in ("smooth", "high"):
                    c = cell(rows, policy, category, mode)
                    if c and c["grip_force"] == c["grip_force"]:  # not NaN
                        lines.append(
                            f"| {name} | {policy} | {category} | {mode} | {c['success']:.2f} | "
                            f"{c['grip_force']:.1f} | {2 * mu * c['grip_force']:.1f} | "
                            f"{c['peak_pull']:.1f} | {c['peak_slip_ratio']:.2f} | "
                            f"{c['normal_angle_deg']:.0f} |"
                        )
    sweep = load("grip_sweep/*/table2.csv") if list(RESULTS.glob("grip_sweep/*/table2.csv")) else {}
    if sweep:
        lines += [
            "",
            "## Where the trap appears: the grip force",
            "",
            "A sensitivity run, not a calibration: `heuristic_pull` with `franka_hand` and "
            "elliptic cones at a lower continuous grasp force per jaw "
            "(`gripper.grasp_force=F`; `grip_sweep/*/table2.md`; drawers), next to the presets' "
            "actual drives (70 N; Menagerie's servo, about 0.3 N on a 12 mm bar). Success "
            "smooth -> normal -> high, and the slip ratio at the peak pull in high:",
            "",
            "| grip per jaw | knob | slip ratio (high) | finger pull | slip ratio (high) |",
            "|---|---|---:|---|---:|",
        ]
        for name, rows in sweep.items():
            cells = []
            for category in ("knob", "finger_pull"):
                found = [cell(rows, "heuristic_pull", category, m) for m in MODES]
                cells.append(" -> ".join(f"{c['success']:.2f}" for c in found))
                ratio = found[2]["peak_slip_ratio"]
                cells.append(f"{ratio:.2f}" if ratio == ratio else "no pull")
            force = name.rsplit("_", 1)[-1].removesuffix("N")
            lines.append(f"| {force} N | " + " | ".join(cells) + " |")
    plot(presets, RESULTS / "success.png")
    (RESULTS / "report.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
