"""`realikea eval table`: the paper's Table 2 grid, policy x category x resistance, to CSV/markdown.

Every cell runs `episodes` episodes with the contact-force strategy classifier on, on the
held-out parts (`asset.split=test`) unless the command line sets asset.split. One env pool
per (category, resistance) serves all policies, so they meet the same configurations and the
same poses (env i, seed env.seed + i; randomized with dr=randomized, nominal under the default
two_phase).
"""

from __future__ import annotations

import csv
import io
import json

import numpy as np
from omegaconf import DictConfig

from realikea.assets.catalog import effective_split
from realikea.assets.split import with_default_split
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.protocol import run_episodes
from realikea.files import atomic_write_text, repo_path
from realikea.markdown import table
from realikea.policies.registry import make_policy
from realikea.pool.env_pool import EnvPool
from realikea.tasks.contacts import STRATEGIES
from realikea.tasks.outcome import OUTCOMES

# per-episode contact statistics averaged over a cell's episodes that had a pulling phase
CONTACT_STATS = (
    "friction_share", "front_share", "peak_pull", "grip_force", "peak_slip_ratio",
    "normal_angle_deg",
)  # fmt: skip
TITLES = {"knob": "Knobs", "finger_pull": "Finger-pull handles", "two_point": "Two-point handles"}


def cell_config(overrides: list[str], policy: str, category: str, resistance: str) -> DictConfig:
    """The composed config of one cell: the command line, then the cell's groups; the test
    split of the parts unless the command line sets asset.split."""
    cfg = load_config(
        with_default_split(
            [*overrides, f"policy={policy}", f"asset={category}", f"resistance={resistance}"],
            "test",
        ),
        "eval",
    )
    cfg.asset.kind = cfg.table.kind
    return cfg


def cell_row(cfg: DictConfig, policy: str, category: str, resistance: str, result) -> dict:
    """One CSV row: the preset, the cell, F/P/S, strategy fractions and contact statistics."""
    summary = result.summary()
    row = {
        "gripper": cfg.gripper.name, "contact": cfg.contact.name,
        "collision": cfg.collision.source, "scene": cfg.scene.name,
        "kind": cfg.asset.kind or "all", "split": effective_split(cfg.asset),
        "policy": policy, "category": category, "resistance": resistance,
        "episodes": summary["episodes"],
        **{o: summary[o] for o in OUTCOMES},
        **{f"strategy_{s}": summary.get("strategies", {}).get(s, 0.0) for s in STRATEGIES},
    }  # fmt: skip
    return {**row, **contact_means(result.episodes)}


def pulled(episodes: list[dict]) -> list[dict]:
    """The episodes that had a pulling phase (the ones with contact statistics)."""
    return [e for e in episodes if e.get("pull_seconds", 0) > 0]


def contact_means(episodes: list[dict]) -> dict[str, float]:
    """Each of CONTACT_STATS averaged over the episodes that had a pulling phase (NaN if none)."""
    chosen = pulled(episodes)
    nan = float("nan")
    return {s: float(np.mean([e[s] for e in chosen])) if chosen else nan for s in CONTACT_STATS}


def to_csv(rows: list[dict]) -> str:
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=list(rows[0]), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: f"{v:.4g}" if isinstance(v, float) else v for k, v in row.items()})
    return out.getvalue()


def to_markdown(rows: list[dict], policies, categories, resistances) -> str:
    """Table 2's layout: one table per category, policies as rows, F/P/S under each mode;
    then the strategy labels and the slip statistics of every cell."""
    first = rows[0]
    lines = [
        f"# Table 2: gripper={first['gripper']}, contact={first['contact']}, "
        f"collision={first['collision']}, scene={first.get('scene', 'freestanding')}, "
        f"kind={first.get('kind', 'drawer')}, split={first.get('split', 'all')}",
        "",
    ]
    cells = {(r["policy"], r["category"], r["resistance"]): r for r in rows}
    for category in categories:
        header = ["Policy", *(c for m in resistances for c in (f"{m} F", "P", "S"))]
        outcome_rows = []
        for policy in policies:
            values = []
            for mode in resistances:
                r = cells.get((policy, category, mode))
                values += [f"{r[o]:.2f}" for o in OUTCOMES] if r else ["", "", ""]
            outcome_rows.append([policy, *values])
        lines += [f"## {TITLES.get(category, category)}", ""]
        lines += [*table(header, "l" * len(header), outcome_rows), ""]
    header = [
        "policy",
        "category",
        "resistance",
        "S",
        *STRATEGIES,
        "friction share",
        "front share",
        "peak pull",
        "slip ratio",
        "grip",
        "normal angle",
    ]
    cell_rows = [
        [
            r["policy"],
            r["category"],
            r["resistance"],
            f"{r['success']:.2f}",
            *(f"{r[f'strategy_{s}']:.2f}" for s in STRATEGIES),
            f"{r['friction_share']:.2f}",
            f"{r['front_share']:.2f}",
            f"{r['peak_pull']:.1f}",
            f"{r['peak_slip_ratio']:.2f}",
            f"{r['grip_force']:.1f}",
            f"{r['normal_angle_deg']:.0f}",
        ]
        for r in rows
    ]
    lines += [
        "## Strategies and slip statistics per cell",
        "",
        "Strategy: fraction of episodes per classifier label. Friction share: fraction of the "
        "pulling force carried by friction; front share: fraction carried by contacts on the "
        "front off the part (its panel and edges); peak pull (N) and the slip ratio at that "
        "instant (friction pull / (mu x sum of normal forces); 1 = sliding); grip: half the summed "
        "normal force (N); normal angle: force-weighted angle between contact normals and the "
        "opening direction (deg). Averages over the episodes with a pulling phase.",
        "",
        *table(header, "l" * len(header), cell_rows),
    ]  # fmt: skip
    return "\n".join(lines) + "\n"


def run_table(overrides: list[str]) -> int:
    """Evaluate the grid of `cfg.table` and write `table2.csv` and `table2.md` to `table.out`."""
    cfg = load_config(overrides, "eval")
    table = cfg.table
    policies, categories, resistances = (
        list(table[k]) for k in ("policies", "categories", "resistances")
    )
    if not (policies and categories and resistances):
        raise RealIkeaError(
            "table.policies, table.categories and table.resistances must be non-empty"
        )
    episodes = int(cfg.episodes)
    if episodes < 1:
        raise RealIkeaError(f"episodes={episodes}: use 1 or more")
    if "checkpoint" in policies:
        raise RealIkeaError(
            "table runs scripted and sampled policies; evaluate a checkpoint with `realikea eval` "
            "or `realikea eval sweep` (they apply its run's robot and task config)"
        )
    made = {
        p: make_policy(cell_config(overrides, p, categories[0], resistances[0])) for p in policies
    }
    rows = []
    for category in categories:
        for resistance in resistances:
            cfg = cell_config(overrides, policies[0], category, resistance)
            cfg.env.num_envs = min(episodes, int(cfg.env.num_envs))
            with EnvPool.from_config(cfg) as pool:
                for policy in policies:
                    where = f"{category} ({table.kind or 'every kind'}, {cfg.asset.split} split)"
                    print(f"{policy} on {where}, {resistance}", flush=True)
                    result = run_episodes(pool, made[policy], episodes)
                    rows.append(cell_row(cfg, policy, category, resistance, result))
                    print(
                        json.dumps(
                            {
                                k: rows[-1][k]
                                for k in ("policy", "category", "split", "resistance", *OUTCOMES)
                            }
                        )
                    )
    out = repo_path(table.out)
    out.mkdir(parents=True, exist_ok=True)
    atomic_write_text(out / "table2.csv", to_csv(rows))
    markdown = to_markdown(rows, policies, categories, resistances)
    atomic_write_text(out / "table2.md", markdown)
    print(markdown)
    print(f"wrote {out / 'table2.csv'} and {out / 'table2.md'}")
    return 0
