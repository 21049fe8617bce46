"""The library-wide fidelity report: CoACD against the single convex hull for every part.

``run_report`` builds (or reuses from the cache) every part's meshes, measures both collision
sources against the visual mesh in a process pool (one task per part), and writes into one folder:

* ``parts.csv``: one row per part: piece, vertex and face counts, E(Q->P) and E(P->Q)
  mean/median/p90/max (metres) for each source, and both means over the exposed surface only
  (without the mounting face, which the clipping of workflow step 3 puts a clearance off);
* ``summary.md``: per-category table of CoACD against the hull, mesh statistics, the command;
* ``distribution.png``: per-part mean, median and P90 of dist(q, P) per category (paper fig. 4);
* ``heatmaps_<category>.png``: visual mesh and the three distance fields of a few parts (fig. 5);
* ``mesh_stats.png``: vertex counts and face areas of the visual and collision meshes (appendix).

Every file is written to a temporary sibling and moved into place with ``os.replace``, so an
interrupted report never leaves a half-written file.
"""

from __future__ import annotations

import csv
import io
import os
import tempfile
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh
from omegaconf import DictConfig
from tqdm import tqdm

from realikea.assets.build import (
    PartMeshes,
    WorkflowSettings,
    build_parts,
    ensure_part,
    part_key,
)
from realikea.assets.catalog import CATEGORIES, Catalog, Part
from realikea.errors import RealIkeaError
from realikea.fidelity import plots
from realikea.fidelity.meshes import load_pair
from realikea.fidelity.metric import (
    DEFAULT_SAMPLES,
    collision_shell,
    point_surface_distance,
    surface_deviation,
)
from realikea.files import repo_path
from realikea.spawn import spawn_context

SOURCES = ("coacd", "hull")
STATS = ("mean", "median", "p90", "max")
DIRECTIONS = ("q_to_p", "p_to_q")
DEFAULT_OUT = "experiments/fidelity"
MM = 1000.0
HEAT_EDGES = 60  # heat-map triangles are split to edges under (bounding-box diagonal / this)
HEAT_TRIANGLES = 60_000  # ... unless that gives more triangles than this per panel
MOUNT_TOL = 1e-5  # m: samples this close to the mounting plane (P) or clip plane (Q) are on it

COLUMNS = (
    "id",
    "category",
    "family",
    "visual_vertices",
    "visual_faces",
    *(
        f"{src}_{col}"
        for src in SOURCES
        for col in (
            "pieces",
            "vertices",
            "faces",
            *(f"{d}_{s}_m" for d in DIRECTIONS for s in STATS),
            *(f"{d}_mean_exposed_m" for d in DIRECTIONS),
        )
    ),
)


# --- measuring one part (runs in a worker process) ----------------------------------------------


@dataclass(frozen=True)
class PartJob:
    """Everything a worker needs to measure one part."""

    part_id: str
    category: str
    family: str
    meshes: PartMeshes
    samples: int
    seed: int
    mount_clearance: float  # the collision input is clipped at z = this (workflow step 3)


@dataclass
class PartResult:
    """One part's CSV row plus the face areas of its meshes (m^2, for the mesh statistics)."""

    row: dict
    face_areas: dict[str, np.ndarray] = field(default_factory=dict)


def measure_part(job: PartJob) -> PartResult:
    """Both collision sources of one part against its visual mesh."""
    row: dict = {"id": job.part_id, "category": job.category, "family": job.family}
    areas: dict[str, np.ndarray] = {}
    visual = None
    for src in SOURCES:
        visual, pieces = load_pair(job.meshes.visual, job.meshes.pieces[src])
        result = surface_deviation(visual, pieces, samples=job.samples, seed=job.seed)
        row[f"{src}_pieces"] = len(pieces)
        row[f"{src}_vertices"] = sum(len(p.vertices) for p in pieces)
        row[f"{src}_faces"] = sum(len(p.faces) for p in pieces)
        for direction, dev in (("q_to_p", result.q_to_p), ("p_to_q", result.p_to_q)):
            for stat in STATS:
                row[f"{src}_{direction}_{stat}_m"] = getattr(dev, stat)
        # the same means over the exposed surface only: without the face screwed to the front
        # (z = 0 on P) and the collision shell's cap on the clip plane (z = mount clearance)
        q_free = result.q_points[:, 2] > job.mount_clearance + MOUNT_TOL
        p_free = result.p_points[:, 2] > MOUNT_TOL
        row[f"{src}_q_to_p_mean_exposed_m"] = _mean_or_nan(result.q_dist[q_free])
        row[f"{src}_p_to_q_mean_exposed_m"] = _mean_or_nan(result.p_dist[p_free])
        areas[src] = np.concatenate([p.area_faces for p in pieces]).astype(np.float32)
    assert visual is not None
    row["visual_vertices"] = len(visual.vertices)
    row["visual_faces"] = len(visual.faces)
    areas["visual"] = visual.area_faces.astype(np.float32)
    return PartResult({k: row[k] for k in COLUMNS}, areas)


def _mean_or_nan(values: np.ndarray) -> float:
    return float(values.mean()) if len(values) else float("nan")


@dataclass
class HeatPanel:
    """Triangles to draw (n x 3 x 3, metres) and the value at each (None: draw plain)."""

    title: str
    triangles: np.ndarray
    values: np.ndarray | None
    mean: float | None = None  # the metric's mean for this field (metres)


@dataclass
class HeatRow:
    """The four panels of one part: P, dist(p, Q), dist(q, P) on CoACD, dist(q', P) on the hull."""

    part_id: str
    family: str
    label: str
    panels: list[HeatPanel]


def split_triangles(
    triangles: np.ndarray, max_edge: float, limit: int | None = None
) -> np.ndarray | None:
    """Bisect each triangle's longest edge until no edge is longer than ``max_edge``.

    Each triangle is split on its own (the result has T-junctions, harmless for drawing), so a
    long sliver becomes a row of pieces instead of the 4^k of midpoint subdivision. Winding is
    kept. Returns None as soon as the result would exceed ``limit`` triangles.
    """
    done = []
    tris = np.asarray(triangles, dtype=np.float64)
    while len(tris):
        if limit is not None and sum(map(len, done)) + len(tris) > limit:
            return None
        edges = np.linalg.norm(tris[:, [1, 2, 0]] - tris, axis=2)  # edge k runs k -> k+1
        long = edges.max(axis=1) > max_edge
        done.append(tris[~long])
        tris, k = tris[long], edges[long].argmax(axis=1)
        order = (np.arange(3)[None, :] + k[:, None]) % 3  # rotate: the longest edge is 0 -> 1
        t = np.take_along_axis(tris, order[:, :, None], axis=1)
        mid = (t[:, 0] + t[:, 1]) / 2
        tris = np.concatenate(
            [np.stack([t[:, 0], mid, t[:, 2]], axis=1), np.stack([mid, t[:, 1], t[:, 2]], axis=1)]
        )
    return np.concatenate(done)


def split_within(triangles: np.ndarray, max_edge: float, budget: int) -> np.ndarray:
    """``split_triangles`` at the finest edge length from ``max_edge`` up that fits ``budget``."""
    triangles = np.asarray(triangles, dtype=np.float64)
    if len(triangles) >= budget:
        return triangles
    while (tris := split_triangles(triangles, max_edge, budget)) is None:
        max_edge *= 1.4
    return tris


def heat_row(
    job: PartJob,
    row: dict,
    label: str,
    edges: int = HEAT_EDGES,
    budget: int = HEAT_TRIANGLES,
) -> HeatRow:
    """Distance fields on the shells of one part, one value per (split) triangle's centre."""
    visual, coacd = load_pair(job.meshes.visual, job.meshes.pieces["coacd"])
    _, hull = load_pair(job.meshes.visual, job.meshes.pieces["hull"])
    q, q_hull = collision_shell(coacd), collision_shell(hull)
    max_edge = float(np.linalg.norm(np.ptp(q_hull.vertices, axis=0))) / edges

    def panel(mesh: trimesh.Trimesh, other: trimesh.Trimesh, title: str, mean: float) -> HeatPanel:
        tris = split_within(mesh.triangles, max_edge, budget)
        dist = point_surface_distance(tris.mean(axis=1), other)
        return HeatPanel(title, tris.astype(np.float32), dist.astype(np.float32), mean)

    return HeatRow(
        job.part_id,
        job.family,
        label,
        [
            HeatPanel("visual mesh P", np.asarray(visual.triangles, dtype=np.float32), None),
            panel(visual, q, "dist(p, Q) on P, CoACD", row["coacd_p_to_q_mean_m"]),
            panel(q, visual, "dist(q, P) on Q, CoACD", row["coacd_q_to_p_mean_m"]),
            panel(q_hull, visual, "dist(q', P) on Q', hull", row["hull_q_to_p_mean_m"]),
        ],
    )


# --- the report ----------------------------------------------------------------------------------


@dataclass
class ReportResult:
    """Where the report went and what it measured."""

    out: Path
    rows: list[dict]
    files: list[Path]
    seconds: float
    headline: str
    failed: dict[str, str] = field(default_factory=dict)  # part id -> why it could not be built


def select_parts(catalog: Catalog, cfg: DictConfig, part_ids: Sequence[str] | None) -> list[Part]:
    """The parts to report: the given ids, else the config's asset selection (all by default)."""
    if part_ids:
        return [catalog.part(pid) for pid in dict.fromkeys(part_ids)]
    if cfg.asset.get("part"):
        return [catalog.part(cfg.asset.part)]
    return catalog.parts_in(cfg.asset.category)


def _exposed_swelling(row: dict) -> float:
    value = row.get("coacd_q_to_p_mean_exposed_m", float("nan"))
    return row["coacd_q_to_p_mean_m"] if np.isnan(value) else value


def heatmap_parts(rows: list[dict], per_category: int) -> dict[str, list[tuple[dict, str]]]:
    """Per category, ``per_category`` parts spread from the median to the worst CoACD swelling.

    Ranked by CoACD's E(Q->P) over the exposed surface (without the mounting cap: it is one mount
    clearance off for every part and hidden against the front). With one part, the typical
    (median) one; with more, the last is the worst, so the heat maps show both what CoACD
    usually achieves and where it is weakest. Between them a new family is preferred.
    """
    chosen: dict[str, list[tuple[dict, str]]] = {}
    for category in CATEGORIES:
        ranked = sorted((r for r in rows if r["category"] == category), key=_exposed_swelling)
        n, k = len(ranked), min(per_category, len(ranked))
        if k == 0:
            continue
        mid = (n - 1) // 2
        targets = [mid] if k == 1 else [round(t) for t in np.linspace(mid, n - 1, k)]
        picked: list[int] = []
        for i, target in enumerate(targets):
            free = sorted((j for j in range(n) if j not in picked), key=lambda j: abs(j - target))
            if k > 1 and i == k - 1:
                j = free[0]  # the worst (or the nearest still free)
            else:
                families = {ranked[p]["family"] for p in picked}
                j = next((j for j in free if ranked[j]["family"] not in families), free[0])
            picked.append(j)
        picks = []
        for j in picked:
            rank = f"rank {j + 1}/{n}"
            kind = "worst CoACD" if j == n - 1 and n > 1 else "typical" if j == mid else ""
            picks.append((ranked[j], f"{kind}, {rank}" if kind else rank))
        chosen[category] = picks
    return chosen


def csv_text(rows: list[dict]) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: (f"{v:.6e}" if isinstance(v, float) else v) for k, v in row.items()})
    return buffer.getvalue()


def _atomic_save(path: Path, save: Callable[[Path], None]) -> None:
    """Call ``save(tmp)`` on a temporary sibling of ``path``, then move it into place."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=path.suffix)
    os.close(fd)
    try:
        save(Path(tmp))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp's 0600 would make the report private
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _write_text(path: Path, text: str) -> None:
    _atomic_save(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def _save_figure(fig, path: Path, dpi: int) -> None:
    """Save a pyplot-free figure as PNG, atomically."""
    _atomic_save(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format="png"))


def _pool_map(fn, jobs: list, workers: int, desc: str, progress: bool) -> list:
    """``fn`` over ``jobs`` in a process pool (in order), with a progress bar."""
    if not jobs:
        return []
    if workers <= 1 or len(jobs) == 1:
        return [fn(j) for j in tqdm(jobs, desc=desc, disable=not progress)]
    out: list = [None] * len(jobs)
    # fresh interpreters: CoACD's, libigl's and manifold3d's thread pools do not survive a fork
    context = spawn_context()
    with ProcessPoolExecutor(max_workers=min(workers, len(jobs)), mp_context=context) as pool:
        futures = {pool.submit(fn, job): i for i, job in enumerate(jobs)}
        for future in tqdm(as_completed(futures), total=len(jobs), desc=desc, disable=not progress):
            out[futures[future]] = future.result()
    return out


def _ensure_or_error(part: Part, settings: WorkflowSettings, root: Path) -> PartMeshes | str:
    try:
        return ensure_part(part, settings, root)[1]
    except RealIkeaError as err:
        return str(err)


def uncached_parts(parts: list[Part], cfg: DictConfig) -> list[str]:
    """Ids of the parts whose meshes are not in the cache yet (they will be built)."""
    settings, root = WorkflowSettings.from_config(cfg), repo_path(cfg.paths.cache)
    return [
        p.id for p in parts if not (root / "parts" / f"{p.id}-{part_key(p, settings)}").is_dir()
    ]


def part_meshes(
    parts: list[Part], cfg: DictConfig, workers: int, progress: bool
) -> tuple[dict[str, PartMeshes], dict[str, str]]:
    """Every part's cached meshes (built on a miss), and the error of each part that fails.

    The whole selection goes through ``build_parts``; only if a part fails are the parts built
    one by one, so that one broken part costs its own row rather than the whole report.
    """
    settings, root = WorkflowSettings.from_config(cfg), repo_path(cfg.paths.cache)
    try:
        meshes, _ = build_parts(parts, settings, root, workers=workers, progress=progress)
        return meshes, {}
    except RealIkeaError:
        pass
    results = _pool_map(
        _ensure_job, [(p, settings, root) for p in parts], workers, "parts, one by one", progress
    )
    meshes = {p.id: r for p, r in zip(parts, results, strict=True) if not isinstance(r, str)}
    failed = {p.id: r for p, r in zip(parts, results, strict=True) if isinstance(r, str)}
    return meshes, failed


def _ensure_job(args: tuple[Part, WorkflowSettings, Path]) -> PartMeshes | str:
    return _ensure_or_error(*args)


def run_report(
    cfg: DictConfig,
    out: Path | None = None,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    parts_per_category: int = 2,
    parts: Sequence[str] | None = None,
    workers: int | None = None,
    progress: bool = True,
    command: str = "realikea fidelity report",
    heat_triangles: int = HEAT_TRIANGLES,
) -> ReportResult:
    """Measure every selected part with both collision sources and write the report folder."""
    if samples < 1:
        raise RealIkeaError(f"--samples must be at least 1, got {samples}")
    if parts_per_category < 0:
        raise RealIkeaError(f"--parts-per-category must be 0 or more, got {parts_per_category}")
    start = time.perf_counter()
    out = Path(out) if out is not None else repo_path(DEFAULT_OUT)
    workers = workers or os.cpu_count() or 1
    selected = select_parts(Catalog.load(), cfg, parts)
    if not selected:
        raise RealIkeaError("no parts selected")
    to_build = uncached_parts(selected, cfg)
    meshes, failed = part_meshes(selected, cfg, workers, progress)
    build_seconds = time.perf_counter() - start
    clearance = float(cfg.workflow.mount_clearance)
    if not meshes:
        raise RealIkeaError(f"no part could be built: {failed}")
    jobs = [
        PartJob(p.id, p.category, p.family, meshes[p.id], samples, seed, clearance)
        for p in selected
        if p.id in meshes
    ]
    results = _pool_map(measure_part, jobs, workers, "fidelity (parts)", progress)
    rows = [r.row for r in results]
    by_id = {j.part_id: j for j in jobs}

    files: list[Path] = []
    _write_text(out / "parts.csv", csv_text(rows))
    files.append(out / "parts.csv")

    _save_figure(plots.distribution_figure(rows), out / "distribution.png", dpi=130)
    files.append(out / "distribution.png")
    face_areas = {
        key: np.concatenate([r.face_areas[key] for r in results]) for key in ("visual", *SOURCES)
    }
    _save_figure(plots.mesh_stats_figure(rows, face_areas), out / "mesh_stats.png", dpi=120)
    files.append(out / "mesh_stats.png")

    chosen = heatmap_parts(rows, parts_per_category)
    heat_jobs = [
        (by_id[row["id"]], row, label, HEAT_EDGES, heat_triangles)
        for picks in chosen.values()
        for row, label in picks
    ]
    heat = _pool_map(_heat_job, heat_jobs, workers, "heat maps (parts)", progress)
    heat_by_id = {h.part_id: h for h in heat}
    for category, picks in chosen.items():
        fig = plots.heatmap_figure(category, [heat_by_id[r["id"]] for r, _ in picks])
        path = out / f"heatmaps_{category}.png"
        _save_figure(fig, path, dpi=110)
        files.append(path)

    seconds = time.perf_counter() - start
    headline = headline_sentence(rows, failed)
    text = summary_markdown(
        rows, face_areas, command, samples, seed, headline, chosen, failed, clearance,
        timing=(seconds, build_seconds, len(to_build), len(selected)),
    )  # fmt: skip
    _write_text(out / "summary.md", text)
    files.append(out / "summary.md")
    return ReportResult(out, rows, files, time.perf_counter() - start, headline, failed)


def _heat_job(args: tuple[PartJob, dict, str, int, int]) -> HeatRow:
    return heat_row(*args)


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
    if timing is None:
        run = ""
    else:
        seconds, building, built, total = timing
        cached = (
            f"{building:.0f} s of it building the collision meshes of {built} of {total} parts "
            "(steps 1-4), the others from the cache"
            if built
            else "every part's collision meshes from the cache"
        )
        run = f" Run time {seconds:.0f} s on {os.cpu_count()} cores, {cached}."
    means = category_means(rows)
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
        "| category | parts | metric | CoACD | hull | hull / CoACD |",
        "|---|---:|---|---:|---:|---:|",
    ]
    metrics = (
        ("E(Q→P) mean", "q_to_p_mean_m"),
        ("E(Q→P) median", "q_to_p_median_m"),
        ("E(Q→P) P90", "q_to_p_p90_m"),
        ("E(Q→P) max", "q_to_p_max_m"),
        ("E(P→Q) mean", "p_to_q_mean_m"),
        ("E(Q→P) mean, exposed", "q_to_p_mean_exposed_m"),
        ("E(P→Q) mean, exposed", "p_to_q_mean_exposed_m"),
    )
    for category, m in means.items():
        first = True
        for label, key in metrics:
            c, h = m[f"coacd_{key}"], m[f"hull_{key}"]
            head = f"{category} | {m['parts']}" if first else " | "
            lines.append(f"| {head} | {label} | {_mm(c)} | {_mm(h)} | {_ratio(h, c)} |")
            first = False
        lines.append(
            f"|  |  | convex pieces | {m['coacd_pieces']:.1f} | {m['hull_pieces']:.0f} |  |"
        )
    worst = sorted(rows, key=lambda r: r["coacd_q_to_p_mean_m"], reverse=True)[:5]
    lines += [
        "",
        "Parts where CoACD swells most (E(Q→P), mm; sorted by the mean):",
        "",
        "| part | family | pieces | CoACD mean | exposed | P90 | max | hull mean | exposed |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in worst:
        lines.append(
            f"| {r['id']} | {r['family']} | {r['coacd_pieces']} | {_mm(r['coacd_q_to_p_mean_m'])} "
            f"| {_mm(r['coacd_q_to_p_mean_exposed_m'])} | {_mm(r['coacd_q_to_p_p90_m'])} "
            f"| {_mm(r['coacd_q_to_p_max_m'])} | {_mm(r['hull_q_to_p_mean_m'])} "
            f"| {_mm(r['hull_q_to_p_mean_exposed_m'])} |"
        )
    if failed:
        lines += ["", "## Parts not measured", "", "The workflow (steps 1-4) failed for:", ""]
        lines += [f"- `{pid}`: {error}" for pid, error in failed.items()]
    lines += ["", "## Mesh statistics", "", *mesh_stats_lines(rows, face_areas)]
    lines += ["", "## Files", ""]
    lines += [
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
    return "\n".join(lines) + "\n"


def mesh_stats_lines(rows: list[dict], face_areas: dict[str, np.ndarray]) -> list[str]:
    """Median vertex and face counts per part and face areas for each mesh kind."""
    lines = [
        "Per part (median [min–max]); CoACD and hull counts are summed over the convex pieces; "
        "face areas over all faces of all parts.",
        "",
        "| mesh | vertices per part | faces per part | median face area (mm²) | "
        "P10–P90 face area (mm²) |",
        "|---|---:|---:|---:|---:|",
    ]
    for key, name in (("visual", "visual P"), ("coacd", "CoACD pieces"), ("hull", "hull")):
        v, f = _col(rows, f"{key}_vertices"), _col(rows, f"{key}_faces")
        a = face_areas[key].astype(float) * 1e6
        lines.append(
            f"| {name} | {np.median(v):,.0f} [{v.min():,.0f}–{v.max():,.0f}] "
            f"| {np.median(f):,.0f} [{f.min():,.0f}–{f.max():,.0f}] | {np.median(a):.3g} "
            f"| {np.percentile(a, 10):.3g}–{np.percentile(a, 90):.3g} |"
        )
    p = _col(rows, "coacd_pieces")
    lines += [
        "",
        f"CoACD convex pieces per part: median {np.median(p):.0f}, "
        f"range {p.min():.0f}–{p.max():.0f}, total {p.sum():,.0f}.",
    ]
    return lines
