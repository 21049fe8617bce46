"""The PyBullet parity's headline figures (results/pybullet_figures.json), which the study's README
quotes by key: pass counts, the largest differences per kind, and what PyBullet does not express.
Relative differences are fractions; lengths and angles in the unit their key names."""

from __future__ import annotations

from parity_measure import Clearance, ProbeRun, Pull
from parity_unexpressed import Unexpressed

from realikea.interop.pybullet_sim import PYBULLET_BODY_DAMPING

KINDS = ("drawer", "door", "flap")
MILLI_UNIT = {"slide": "mm", "hinge": "mrad"}


def span(values: list[float]) -> list[float]:
    """[smallest, largest]."""
    return [min(values), max(values)]


def pull_figures(pulls: list[Pull]) -> dict:
    """How many pulls pass, and per kind the largest difference after 1 s and before the stop
    among the pulls that open."""
    opening = [p for p in pulls if p.result.expected == "opens"]
    return {
        "passed": sum(p.result.passed for p in pulls),
        "total": len(pulls),
        "largest_difference": {
            kind: {
                "after_1s": max(p.result.difference for p in opening if p.kind == kind),
                "before_stop": max(p.result.difference_then for p in opening if p.kind == kind),
            }
            for kind in KINDS
        },
    }


def probe_figures(probes: list[ProbeRun], clearances: list[Clearance]) -> dict:
    """How many probe runs pass; how much narrower PyBullet sees each gap (mm) and how much
    earlier it stops the probe on the hull (mm)."""
    hull = [p.result for p in probes if p.source == "hull"]
    return {
        "passed": sum(p.result.passed for p in probes),
        "total": len(probes),
        "gap_narrower_mm": span([1e3 * (c.mujoco - c.pybullet) for c in clearances]),
        "hull_stops_earlier_mm": span([1e3 * (r.mujoco - r.pybullet) for r in hull]),
    }


def per_kind(records, value) -> dict:
    """Per kind, the largest value over its configurations (`value(record)`)."""
    return {kind: max(value(r) for r in records if r.kind == kind) for kind in KINDS}


def unexpressed_figures(found: Unexpressed) -> dict:
    """Joint motor, damping, time step, creep and joint limits, in figures."""
    milli = {c.kind: MILLI_UNIT[c.joint_type] for c in found.creep}
    return {
        "friction": {
            "configuration": found.hold_id,
            "step_s": found.hold_step,
            "motor_holds_n": 1 / found.hold_step,
            "opening_m": {f"at_{100 * s:.0f}_percent": found.hold[s] for s in sorted(found.hold)},
            "largest_breakaway_n": found.largest_breakaway,
            "motor_over_breakaway": 1 / found.hold_step / found.largest_breakaway,
        },
        "damping": {
            "urdf_vs_hand": max(d.difference for d in found.damping),
            "body_damping": PYBULLET_BODY_DAMPING,
            "body_damping_difference": span([d.damped_body_difference for d in found.damping]),
        },
        "time_step": {
            s.kind: {
                "coarse": s.coarse,
                "fine": s.fine,
                "mujoco": s.mujoco,
                "pybullet": s.pybullet,
            }
            for s in found.steps
        },  # fmt: skip
        "creep_milli": {
            "unit": milli,
            "mujoco": per_kind(found.creep, lambda c: 1e3 * c.mujoco),
            "pybullet": per_kind(found.creep, lambda c: 1e3 * c.pybullet),
        },
        "past_limit_milli": {
            "unit": milli,
            "mujoco": per_kind(found.limits, lambda e: 1e3 * e.mujoco),
            "pybullet": per_kind(found.limits, lambda e: 1e3 * e.pybullet),
        },
    }


def figures(pulls, probes, clearances, found, provenance: dict) -> dict:
    """Everything the README quotes, with how it was made."""
    return {
        **provenance,
        "pulls": pull_figures(pulls),
        "probe": probe_figures(probes, clearances),
        **unexpressed_figures(found),
    }
