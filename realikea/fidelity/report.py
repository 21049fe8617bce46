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

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from omegaconf import DictConfig

from realikea.assets.build import (
    PartMeshes,
    WorkflowSettings,
    build_parts,
    ensure_part,
    part_key,
)
from realikea.assets.catalog import Catalog, Part
from realikea.errors import RealIkeaError
from realikea.fidelity import plots
from realikea.fidelity.heatmap import HEAT_EDGES, HEAT_TRIANGLES, HeatRow, heat_row, heatmap_parts
from realikea.fidelity.measure import PartJob, measure_part
from realikea.fidelity.metric import (
    DEFAULT_SAMPLES,
)
from realikea.fidelity.summary import csv_text, headline_sentence, summary_markdown
from realikea.files import atomic_path, atomic_write_text, repo_path
from realikea.sources import SOURCES
from realikea.spawn import process_map

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
    results = process_map(
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
    out = Path(out) if out is not None else repo_path(cfg.paths.fidelity_report)
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
    results = process_map(measure_part, jobs, workers, "fidelity (parts)", progress)
    rows = [r.row for r in results]
    by_id = {j.part_id: j for j in jobs}

    files: list[Path] = []
    atomic_write_text(out / "parts.csv", csv_text(rows))
    files.append(out / "parts.csv")

    save_figure(plots.distribution_figure(rows), out / "distribution.png", dpi=130)
    files.append(out / "distribution.png")
    face_areas = {
        key: np.concatenate([r.face_areas[key] for r in results]) for key in ("visual", *SOURCES)
    }
    save_figure(plots.mesh_stats_figure(rows, face_areas), out / "mesh_stats.png", dpi=120)
    files.append(out / "mesh_stats.png")

    chosen = heatmap_parts(rows, parts_per_category)
    heat_jobs = [
        (by_id[row["id"]], row, label, HEAT_EDGES, heat_triangles)
        for picks in chosen.values()
        for row, label in picks
    ]
    heat = process_map(_heat_job, heat_jobs, workers, "heat maps (parts)", progress)
    heat_by_id = {h.part_id: h for h in heat}
    for category, picks in chosen.items():
        fig = plots.heatmap_figure(category, [heat_by_id[r["id"]] for r, _ in picks])
        path = out / f"heatmaps_{category}.png"
        save_figure(fig, path, dpi=110)
        files.append(path)

    seconds = time.perf_counter() - start
    headline = headline_sentence(rows, failed)
    text = summary_markdown(
        rows, face_areas, command, samples, seed, headline, chosen, failed, clearance,
        timing=(seconds, build_seconds, len(to_build), len(selected)),
    )  # fmt: skip
    atomic_write_text(out / "summary.md", text)
    files.append(out / "summary.md")
    return ReportResult(out, rows, files, time.perf_counter() - start, headline, failed)


def _heat_job(args: tuple[PartJob, dict, str, int, int]) -> HeatRow:
    return heat_row(*args)


def save_figure(fig, path: Path, dpi: int) -> None:
    """Save a pyplot-free figure as PNG, atomically."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png")
