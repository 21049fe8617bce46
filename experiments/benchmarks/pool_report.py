"""The env pool benchmark's record (what one run measured), the figures derived from it, and its
report: tables only; what they mean is written in README.md ("Env pool"), which quotes the
figures by key (`realikea/reports/quotes.py`)."""

from __future__ import annotations

import json
from dataclasses import asdict
from pathlib import Path

from pool_record import Measured

from realikea.files import atomic_write_text
from realikea.markdown import table

COMMAND = "python experiments/benchmarks/bench_pool.py"


# short keys of the breakdown's parts, in its order (the figures' `profile.parts`)
PART_KEYS = ("ik", "action_mapping", "physics", "observation", "reward", "resets", "bookkeeping")


def figures(m: Measured) -> dict:
    """Every figure the report shows and README.md quotes, by key."""
    busy = sum(v for _, v in m.parts)
    ms = dict(zip(PART_KEYS, (v for _, v in m.parts), strict=True))
    share, transfer = ms["physics"] / busy, m.transfer_ms / m.wall_ms
    own = ms["bookkeeping"] / busy + transfer
    mj_step_us = ms["physics"] / m.decimation * 1e3
    rates = [
        {**r._asdict(), "pool_over_limit": r.pool / r.limit, "pool_over_async": r.pool / r.vec}
        for r in m.rows
    ]
    pool_d, serial_d, threaded_d, limit_d, limit_1 = m.design.values()
    coacd, hull = m.sources["coacd"], m.sources["hull"]
    return {
        "rates": rates,
        "at_32": next(
            ({**r, "async_over_limit": r["vec"] / r["limit"]} for r in rates if r["envs"] == 32),
            None,
        ),
        "profile": {
            "envs": m.profile_envs,
            "rate": m.profile_rate,
            "limit": m.profile_limit,
            "core_share": m.core_share,
            "parts": {k: {"ms": v, "share": v / busy} for k, v in ms.items()},
            "total_ms": busy,
            "wall_ms": m.wall_ms,
            "transfer_ms": m.transfer_ms,
            "transfer_share": transfer,
            "physics_share": share,
            "own_share": own,
            "ceiling_mj_step": share * (1 - transfer),
            "rollout_us": m.rollout_us,
            "mj_step_us": mj_step_us,
            "rollout_over_mj_step": m.rollout_us / mj_step_us,
            "ceiling_rollout": min(1.0, share * m.rollout_us / mj_step_us) * (1 - transfer),
        },
        "design": {
            "rates": m.design,
            "workers_over_serial": pool_d / serial_d,
            "threaded_over_serial": threaded_d / serial_d,
            "ceiling_all_parallel": m.cores * (1 - own),
            "ceiling_physics_parallel": 1 / (1 - share + share / m.cores),
            "physics_threads_gain": limit_d / limit_1,
        },
        "sources": {
            "coacd": coacd._asdict(),
            "hull": hull._asdict(),
            "coacd_over_hull": coacd.physics_us / hull.physics_us,
        },
    }


def _rates(f: dict) -> list[str]:
    header = [
        "envs",
        "steps × best of",
        "pool",
        "physics limit",
        "AsyncVectorEnv",
        "pool / physics",
        "pool / Async",
        "contacts per env",
        "replay max abs dstate",
        "startup pool / Async (s)",
    ]
    rows = [
        [
            str(r["envs"]),
            f"{r['steps']} × {r['best_of']}",
            f"{r['pool']:.0f}",
            f"{r['limit']:.0f}",
            f"{r['vec']:.0f}",
            f"{r['pool_over_limit']:.2f}",
            f"{r['pool_over_async']:.2f}",
            f"{r['contacts']:.1f}",
            f"{r['deviation']:.1e}",
            f"{r['pool_start']:.1f} / {r['vec_start']:.1f}",
        ]
        for r in f["rates"]
    ]
    return ["## Control steps per second", "", *table(header, "r" * len(header), rows)]  # fmt: skip


def _targets(r: dict) -> list[str]:
    return ["## Targets at 32 envs", ""] + table(
        ["target", "measured", "met"], "lrl",
        [
            ["pool ≥ 0.9 × physics limit", f"{r['pool_over_limit']:.2f}",
             "yes" if r["pool_over_limit"] >= 0.9 else "no"],
            ["pool ≥ 2 × AsyncVectorEnv", f"{r['pool_over_async']:.2f}",
             "yes" if r["pool_over_async"] >= 2 else "no"],
            ["AsyncVectorEnv / physics limit", f"{r['async_over_limit']:.2f}", "–"],
        ],
    )  # fmt: skip


def _profile(m: Measured, p: dict) -> list[str]:
    lines = [f"## Where the time goes ({p['envs']} envs, profiled run)", ""]
    lines += table(
        ["profiled run", "value"], "lr",
        [
            ["pool", f"{p['rate']:.0f} steps/s"],
            ["physics limit", f"{p['limit']:.0f} steps/s"],
            ["a worker's share of a core while stepping", f"{p['core_share']:.0%}"],
        ],
    )  # fmt: skip
    parts = [[name, f"{value:.3f}", f"{value / p['total_ms']:.0%}"] for name, value in m.parts]
    parts.append(["**total per env-step**", f"**{p['total_ms']:.3f}**", "100%"])
    derived = [
        ["main process per pool step: wall", f"{p['wall_ms']:.1f} ms"],
        ["of which transfer (signalling, shared-memory copies, waiting beyond the slowest "
         "worker's compute)", f"{p['transfer_ms']:.2f} ms ({p['transfer_share']:.1%})"],
        ["physics, share of the workers' CPU per env-step", f"{p['physics_share']:.0%}"],
        ["the pool's own cost (bookkeeping + transfer)", f"{p['own_share']:.1%}"],
        ["ceiling against raw `mj_step` on every core (physics share × (1 − transfer))",
         f"{p['ceiling_mj_step']:.2f}"],
        ["rollout per physics step (CPU, it also records the state) / `mj_step` in the workers",
         f"{p['rollout_us']:.1f} / {p['mj_step_us']:.1f} µs = {p['rollout_over_mj_step']:.2f}×"],
        ["ceiling against the rollout limit", f"{p['ceiling_rollout']:.2f}"],
    ]  # fmt: skip
    return [*lines, "", *table(["part", "ms per env-step", "share"], "lrr", parts), "",
            *table(["derived", "value"], "lr", derived)]  # fmt: skip


def _design(m: Measured, d: dict) -> list[str]:
    ratios = [
        ["worker processes / serial loop", f"{d['workers_over_serial']:.2f}×"],
        ["physics threaded through `mujoco.rollout`, the rest serial / serial loop",
         f"{d['threaded_over_serial']:.2f}×"],
        [f"ceiling on {m.cores} cores, everything but the pool's own cost in parallel",
         f"{d['ceiling_all_parallel']:.2f}×"],
        [f"ceiling on {m.cores} cores, only the physics in parallel",
         f"{d['ceiling_physics_parallel']:.2f}×"],
        [f"pure physics, {m.cores} threads / 1 thread, in this window",
         f"{d['physics_threads_gain']:.2f}×"],
    ]  # fmt: skip
    return [
        f"## Design check ({m.design_envs} envs, interleaved, best of {m.design_best_of})",
        "",
        *table(["how", "steps/s"], "lr", [[n, f"{v:.0f}"] for n, v in d["rates"].items()]),
        "",
        *table(["ratio", "value"], "lr", ratios),
    ]


def _sources(m: Measured, s: dict) -> list[str]:
    rows = [
        [name, f"{c['physics_us']:.1f}", f"{c['contacts']:.1f}", f"{c['geoms']:.0f}"]
        for name, c in (("CoACD", s["coacd"]), ("hull", s["hull"]))
    ]
    header = ["source", "µs per physics step", "contacts (mean ncon)", "geoms per scene"]
    return [
        f"## CoACD vs hull physics cost ({m.source_envs} configurations, same scripted "
        "policy, single thread)",
        "",
        *table(header, "lrrr", rows),
        "",
        *table(["ratio", "value"], "lr",
               [["CoACD / hull, per physics step", f"{s['coacd_over_hull']:.2f}×"]]),
    ]  # fmt: skip


def render(m: Measured, f: dict) -> str:
    """bench_pool.md: the record's header and the tables of the figures."""
    header = [
        "# Env pool benchmark",
        "",
        f"Command: `{COMMAND}` (record [`bench_pool.json`](bench_pool.json), figures "
        "[`bench_pool_figures.json`](bench_pool_figures.json); method and reading: "
        "[README.md](README.md#env-pool)).",
        "",
        f"Machine: {m.machine}; " + ", ".join(f"{name} {v}" for name, v in m.versions.items())
        + f". Load average {m.load[0]:.1f} at the start, {m.load[1]:.1f} at the end. "
        f"Whole run: {m.minutes:.1f} min.",
    ]  # fmt: skip
    sections = [header, _rates(f)]
    if f["at_32"] is not None:
        sections.append(_targets(f["at_32"]))
    sections += [_profile(m, f["profile"]), _design(m, f["design"]), _sources(m, f["sources"])]
    return "\n\n".join("\n".join(s) for s in sections) + "\n"


def write_report(m: Measured, out: Path) -> None:
    """The report `out` (.md) and its figures beside it (`<stem>_figures.json`)."""
    f = figures(m)
    atomic_write_text(out.with_name(out.stem + "_figures.json"), json.dumps(f, indent=1) + "\n")
    atomic_write_text(out, render(m, f))


def write_record(m: Measured, out: Path) -> None:
    """The record of a run (`out` with .json), then its report."""
    atomic_write_text(out.with_suffix(".json"), json.dumps(asdict(m), indent=1) + "\n")
    write_report(m, out)
