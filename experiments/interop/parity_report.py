"""The PyBullet parity as tables (results/pybullet.md) and figures (results/pybullet_figures.json);
what they mean is written in the study's README, which quotes the figures by key."""

from __future__ import annotations

from parity_measure import Clearance, ProbeRun, Pull
from parity_unexpressed import FINE_STEP, Unexpressed

from realikea.interop.pybullet_sim import PYBULLET_BODY_DAMPING
from realikea.interop.sample import UNIT
from realikea.markdown import table


def opening(value: float, joint_type: str) -> str:
    """An opening with its unit (the SAPIEN check's table too)."""
    value = value if abs(value) >= 5e-5 else 0.0  # no "-0.0000"
    return f"{value:.4f} {UNIT[joint_type]}"


def percent(value: float | None) -> str:
    """A relative difference in percent, or a dash where there is none."""
    return "–" if value is None else f"{100 * value:.2f} %"


def _section(title: str, header: list[str], align: str, rows: list[list[str]]) -> list[str]:
    return [f"## {title}", "", *table(header, align, rows), ""]


def _against(value: float, difference: float, joint_type: str) -> str:
    """An opening and its relative difference from MuJoCo's."""
    return f"{opening(value, joint_type)} = {percent(difference)}"


def _verdict(passed: bool) -> str:
    return "pass" if passed else "**fail**"


def pull_rows(pulls: list[Pull]) -> list[list[str]]:
    rows = []
    for p in pulls:
        r, jtype = p.result, p.joint_type
        rows.append([
            p.config_id, p.kind, p.category, p.mode, f"{p.multiple:g}× = {p.force:.2f} N",
            opening(r.mujoco, jtype) + " (stop)" * p.mujoco_stop,
            opening(r.pybullet, jtype) + " (stop)" * p.pybullet_stop,
            percent(r.difference),
            f"{r.compare_time:.3f} s: {opening(r.mujoco_then, jtype)} / "
            f"{opening(r.pybullet_then, jtype)} = {percent(r.difference_then)}",
            f"{r.mujoco_moved} / {r.pybullet_moved}", _verdict(r.passed),
        ])  # fmt: skip
    return rows


def probe_rows(probes: list[ProbeRun]) -> list[list[str]]:
    return [
        [
            p.config_id, p.source, str(p.pieces), f"{1e3 * p.gap:.1f} mm",
            f"{1e3 * p.result.mujoco:.1f} mm ({p.result.outcome(p.result.mujoco)})",
            f"{1e3 * p.result.pybullet:.1f} mm ({p.result.outcome(p.result.pybullet)})",
            f"{1e3 * p.result.through:.1f} mm", _verdict(p.result.passed),
        ]
        for p in probes
    ]  # fmt: skip


def checked_sections(pulls: list[Pull], probes: list[ProbeRun]) -> list[str]:
    """Check (a), the pulls, and check (b), the fingertip probe."""
    return [
        *_section(
            "(a) Constant pull at the handle for 1 s",
            ["configuration", "kind", "category", "mode", "pull", "MuJoCo after 1 s",
             "PyBullet after 1 s", "difference",
             "before the stop: t, MuJoCo / PyBullet = difference", "verdicts MuJoCo / PyBullet",
             "result"],
            "lllllrrrlll", pull_rows(pulls),
        ),
        *_section(
            "(b) Fingertip probe behind a two-point bar",
            ["configuration", "source", "pieces", "gap behind the bar", "MuJoCo travel",
             "PyBullet travel", "travel to clear", "result"],
            "llrrrrrl", probe_rows(probes),
        ),
    ]  # fmt: skip


def unexpressed_sections(found: Unexpressed, clearances: list[Clearance]) -> list[str]:
    """What PyBullet does not express (high resistance), a table per effect."""
    fine, body = f"{FINE_STEP * 1e3:g} ms", f"{PYBULLET_BODY_DAMPING:g}"
    return [
        *_section(
            "Joint friction: opening after 1 s",
            ["configuration", "pull", "MuJoCo", "PyBullet, emulated", "PyBullet, default motor",
             "PyBullet, friction ignored"],
            "llrrrr",
            [[cid, f"{multiple:g}×", *(opening(v, jtype) for v in models)]
             for cid, jtype, multiple, models in found.friction],
        ),
        *_section(
            "Damping at 1.2× breakaway",
            ["configuration", "URDF damping, after 1 s", "by hand, after 1 s", "difference",
             "no damping, after 1 s"],
            "lrrrr",
            [[d.config_id, opening(d.by_urdf, d.joint_type), opening(d.by_hand, d.joint_type),
              percent(d.difference), opening(d.undamped, d.joint_type)] for d in found.damping],
        ),
        *_section(
            "Body damping: openings at 1.2× breakaway before the stop",
            ["configuration", "t", "MuJoCo", "PyBullet, body damping 0 (used)",
             f"PyBullet, body damping {body} (PyBullet's default)"],
            "lrrrr",
            [[d.config_id, f"{d.then:.3f} s", opening(d.mujoco_then, d.joint_type),
              _against(d.undamped_body_then, d.undamped_body_difference, d.joint_type),
              _against(d.damped_body_then, d.damped_body_difference, d.joint_type)]
             for d in found.damping],
        ),
        *_section(
            f"Time step: 1.2× pulls at 2 ms and at {fine}, before the stop",
            ["configuration", "t", "PyBullet vs MuJoCo at 2 ms", f"at {fine}",
             f"MuJoCo 2 ms vs {fine}", f"PyBullet 2 ms vs {fine}"],
            "lrrrrr",
            [[s.config_id, f"{s.then:.3f} s", percent(s.coarse), percent(s.fine), percent(s.mujoco),
              percent(s.pybullet)] for s in found.steps],
        ),
        *_section(
            "Creep below breakaway: opening after 1 s at 0.5×",
            ["configuration", "MuJoCo", "PyBullet"], "lrr",
            [[c.config_id, opening(c.mujoco, c.joint_type), opening(c.pybullet, c.joint_type)]
             for c in found.creep],
        ),
        *_section(
            "Joint limits: largest excursion past the upper limit under a 2× pull",
            ["configuration", "upper limit", "MuJoCo past it", "PyBullet past it"], "lrrr",
            [[e.config_id, opening(e.upper, e.joint_type), opening(e.mujoco, e.joint_type),
              opening(e.pybullet, e.joint_type)] for e in found.limits],
        ),
        *_section(
            "Contacts: the probe centred under the bar, distance to the pieces (CoACD)",
            ["configuration", "geometric (gap/2 − 4.5 mm)", "MuJoCo", "PyBullet",
             "PyBullet − MuJoCo", "PyBullet, to the front"],
            "lrrrrr",
            [[c.config_id, f"{1e3 * c.geometric:.2f} mm", f"{1e3 * c.mujoco:.2f} mm",
              f"{1e3 * c.pybullet:.2f} mm", f"{1e3 * (c.pybullet - c.mujoco):+.2f} mm",
              f"{1e3 * c.to_front:.2f} mm"] for c in clearances],
        ),
    ]  # fmt: skip


def report(pulls, probes, clearances, found, provenance: str) -> str:
    """results/pybullet.md: the tables, under the line that says how they were made."""
    lines = [
        "# PyBullet against MuJoCo: the exported models pulled and probed",
        "",
        f"{provenance} Method and reading: [the study's README](../README.md).",
        "",
        *checked_sections(pulls, probes),
        *unexpressed_sections(found, clearances),
    ]
    return "\n".join(lines).rstrip("\n") + "\n"
