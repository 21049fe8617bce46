"""The fidelity report's words: per-category means, the headline sentence, the summary page and
its mesh-statistics lines, and the per-part CSV."""

from __future__ import annotations

import csv
import io
import os

import numpy as np

from realikea.assets.catalog import CATEGORIES
from realikea.fidelity.measure import COLUMNS, MM
from realikea.markdown import table


def csv_text(rows: list[dict]) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: (f"{v:.6e}" if isinstance(v, float) else v) for k, v in row.items()})
    return buffer.getvalue()


# --- summary -----------------------------------------------------------------------------------


def _col(rows: list[dict], key: str) -> np.ndarray:
    return np.array([r[key] for r in rows], dtype=float)


def category_means(rows: list[dict]) -> dict[str, dict[str, float]]:
    """Per category (and ``all``): mean over parts of each per-part statistic."""
    groups = {c: [r for r in rows if r["category"] == c] for c in CATEGORIES}
    groups = {c: g for c, g in groups.items() if g}
    groups["all"] = rows
    keys = [k for k in COLUMNS if k.endswith("_m") or k.endswith("_pieces")]
    return {
        c: {k: float(np.nanmean(_col(g, k))) for k in keys} | {"parts": len(g)}
        for c, g in groups.items()
    }


def _mm(value: float) -> str:
    mm = value * MM
    if mm == 0.0:
        return "0"
    if mm >= 100:
        return f"{mm:.0f}"
    if mm >= 0.001:
        return f"{mm:.3g}"
    return f"{mm:.1e}"


def _ratio(hull: float, coacd: float) -> str:
    if coacd <= 0.0:
        return "—"
    r = hull / coacd
    if r >= 1000:
        return f"{r:,.0f}×"
    return f"{r:.3g}×"


def headline_sentence(rows: list[dict], failed: dict[str, str] | None = None) -> str:
    """One sentence: how much the hull swells against CoACD, where most and least."""
    means = category_means(rows)
    a = means["all"]
    coacd, hull = a["coacd_q_to_p_mean_m"], a["hull_q_to_p_mean_m"]
    text = (
        f"Over {len(rows)} parts, the single convex hull swells {_ratio(hull, coacd)} more "
        f"than CoACD: E(Q→P) averages {_mm(hull)} mm for the hull against {_mm(coacd)} mm for "
        f"CoACD (P90 {_mm(a['hull_q_to_p_p90_m'])} mm against {_mm(a['coacd_q_to_p_p90_m'])} mm)."
    )
    text += (
        f" On the exposed surface (without the mounting face) CoACD's E(Q→P) is "
        f"{_mm(a['coacd_q_to_p_mean_exposed_m'])} mm against the hull's "
        f"{_mm(a['hull_q_to_p_mean_exposed_m'])} mm."
    )
    cats = [c for c in CATEGORIES if c in means]
    if len(cats) > 1:
        gap = {c: means[c]["hull_q_to_p_mean_m"] for c in cats}
        hi, lo = max(gap, key=gap.get), min(gap, key=gap.get)
        text += (
            f" The hull's swelling is largest for {hi.replace('_', '-')} parts "
            f"({_mm(gap[hi])} mm) and smallest for {lo.replace('_', '-')} parts "
            f"({_mm(gap[lo])} mm)."
        )
    worse = [r["id"] for r in rows if r["coacd_q_to_p_mean_m"] >= r["hull_q_to_p_mean_m"]]
    if worse:
        text += f" CoACD is not better than the hull for {', '.join(worse)}."
    if failed:
        text += (
            f" {len(failed)} part{'s' * (len(failed) != 1)} could not be built and "
            f"{'are' if len(failed) != 1 else 'is'} missing: {', '.join(failed)}."
        )
    return text


def _run_sentence(timing: tuple[float, float, int, int] | None) -> str:
    """How long the run took and how many parts it built, or '' without timing."""
    if timing is None:
        return ""
    seconds, building, built, total = timing
    cached = (
        f"{building:.0f} s of it building the collision meshes of {built} of {total} parts "
        "(steps 1-4), the others from the cache"
        if built
        else "every part's collision meshes from the cache"
    )
    return f" Run time {seconds:.0f} s on {os.cpu_count()} cores, {cached}."


SUMMARY_METRICS = (
    ("E(Q→P) mean", "q_to_p_mean_m"),
    ("E(Q→P) median", "q_to_p_median_m"),
    ("E(Q→P) P90", "q_to_p_p90_m"),
    ("E(Q→P) max", "q_to_p_max_m"),
    ("E(P→Q) mean", "p_to_q_mean_m"),
    ("E(Q→P) mean, exposed", "q_to_p_mean_exposed_m"),
    ("E(P→Q) mean, exposed", "p_to_q_mean_exposed_m"),
)
WORST_HEADER = (
    "part", "family", "pieces", "CoACD mean", "exposed", "P90", "max", "hull mean", "exposed",
)  # fmt: skip
# the worst parts' distance columns after part, family and pieces (each key + "_m")
WORST_COLUMNS = (
    "coacd_q_to_p_mean", "coacd_q_to_p_mean_exposed", "coacd_q_to_p_p90", "coacd_q_to_p_max",
    "hull_q_to_p_mean", "hull_q_to_p_mean_exposed",
)  # fmt: skip


def _category_lines(rows: list[dict], clearance: float) -> list[str]:
    """Per category: the means of each statistic for both sources, and their ratio."""
    lines = [
        "## Per category",
        "",
        "Mean over the category's parts of each part's statistic, in millimetres. "
        "E(Q→P) = dist(q, P) from the collision shell to the visual mesh (swelling, what the "
        "paper reports); E(P→Q) = dist(p, Q) from the visual mesh to the collision shell "
        "(visual surface the collision shell misses). *Exposed*: the same means without the "
        "mounting face: both collision sources are clipped "
        f"{clearance * MM:g} mm in front of the mounting plane (workflow step 3), so the "
        "collision shell's cap on the clip plane lies exactly that far from P, and P's mounting "
        "face at least that far from Q; neither can be touched on a mounted part.",
        "",
    ]
    cells = []
    for category, m in category_means(rows).items():
        for i, (label, key) in enumerate(SUMMARY_METRICS):
            c, h = m[f"coacd_{key}"], m[f"hull_{key}"]
            head = [category, str(m["parts"])] if i == 0 else ["", ""]
            cells.append([*head, label, _mm(c), _mm(h), _ratio(h, c)])
        pieces = [f"{m['coacd_pieces']:.1f}", f"{m['hull_pieces']:.0f}", ""]
        cells.append(["", "", "convex pieces", *pieces])
    header = ["category", "parts", "metric", "CoACD", "hull", "hull / CoACD"]
    return lines + table(header, "lrlrrr", cells)


def _worst_cells(row: dict) -> list[str]:
    return [_mm(row[f"{key}_m"]) for key in WORST_COLUMNS]


def _worst_lines(rows: list[dict]) -> list[str]:
    """The five parts where CoACD swells most."""
    worst = sorted(rows, key=lambda r: r["coacd_q_to_p_mean_m"], reverse=True)[:5]
    return [
        "Parts where CoACD swells most (E(Q→P), mm; sorted by the mean):",
        "",
        *table(
            WORST_HEADER,
            "llrrrrrrr",
            [[r["id"], r["family"], str(r["coacd_pieces"])] + _worst_cells(r) for r in worst],
        ),
    ]


def _files_lines(chosen: dict[str, list[tuple[dict, str]]]) -> list[str]:
    """What each file of the report folder holds."""
    lines = [
        "## Files",
        "",
        "- `parts.csv`: one row per part; distances in metres (`*_m`), counts summed over pieces.",
        "- `distribution.png`: per-part mean, median and P90 of dist(q, P) per category (fig. 4).",
        "- `mesh_stats.png`: vertex counts per part and face-area distributions (appendix).",
    ]
    for category, picks in chosen.items():
        shown = ", ".join(f"{r['id']} ({label})" for r, label in picks)
        lines.append(
            f"- `heatmaps_{category}.png`: P, dist(p, Q), dist(q, P) on CoACD, dist(q', P) on the "
            f"hull (fig. 5) for {shown}; ranks by CoACD's E(Q→P) on the exposed surface."
        )
    return lines


def summary_markdown(
    rows: list[dict],
    face_areas: dict[str, np.ndarray],
    command: str,
    samples: int,
    seed: int,
    headline: str,
    chosen: dict[str, list[tuple[dict, str]]],
    failed: dict[str, str] | None = None,
    clearance: float = 0.0,
    timing: tuple[float, float, int, int] | None = None,
) -> str:
    """The report's summary page; ``timing`` = (seconds, of them building, built, parts)."""
    run = _run_sentence(timing)
    lines = [
        "# Collision fidelity: CoACD against the single convex hull",
        "",
        headline,
        "",
        "Produced by (from the repository root):",
        "",
        f"    {command}",
        "",
        f"{samples:,} points per shell (seed {seed}), exact point-to-triangle distances "
        f"(`realikea.fidelity.metric.surface_deviation`); {len(rows)} parts.{run}",
        "",
        *_category_lines(rows, clearance),
        "",
        *_worst_lines(rows),
    ]
    if failed:
        lines += ["", "## Parts not measured", "", "The workflow (steps 1-4) failed for:", ""]
        lines += [f"- `{pid}`: {error}" for pid, error in failed.items()]
    lines += ["", "## Mesh statistics", "", *mesh_stats_lines(rows, face_areas)]
    lines += ["", *_files_lines(chosen)]
    return "\n".join(lines) + "\n"


def mesh_stats_lines(rows: list[dict], face_areas: dict[str, np.ndarray]) -> list[str]:
    """Median vertex and face counts per part and face areas for each mesh kind."""
    lines = [
        "Per part (median [min–max]); CoACD and hull counts are summed over the convex pieces; "
        "face areas over all faces of all parts.",
        "",
    ]
    cells = []
    for key, name in (("visual", "visual P"), ("coacd", "CoACD pieces"), ("hull", "hull")):
        v, f = _col(rows, f"{key}_vertices"), _col(rows, f"{key}_faces")
        a = face_areas[key].astype(float) * 1e6
        cells.append([
            name, f"{np.median(v):,.0f} [{v.min():,.0f}–{v.max():,.0f}]",
            f"{np.median(f):,.0f} [{f.min():,.0f}–{f.max():,.0f}]", f"{np.median(a):.3g}",
            f"{np.percentile(a, 10):.3g}–{np.percentile(a, 90):.3g}",
        ])  # fmt: skip
    header = ["mesh", "vertices per part", "faces per part", "median face area (mm²)"]
    lines += table([*header, "P10–P90 face area (mm²)"], "lrrrr", cells)
    p = _col(rows, "coacd_pieces")
    lines += [
        "",
        f"CoACD convex pieces per part: median {np.median(p):.0f}, "
        f"range {p.min():.0f}–{p.max():.0f}, total {p.sum():,.0f}.",
    ]
    return lines
