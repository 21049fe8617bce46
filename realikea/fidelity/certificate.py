"""A part's fidelity certificate for one collision source: E(Q->P) and E(P->Q) mean, median and
P90 in metres. Read from the fidelity report's parts.csv when its row counts exactly the meshes
being certified (vertices, faces, pieces), else measured afresh with the report's own metric and
defaults (`surface_deviation`, 100,000 points per shell, seed 0), so a certificate never
describes other meshes than the ones it ships with."""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path

from omegaconf import DictConfig

from realikea.config import load_config
from realikea.fidelity.measure import DIRECTIONS
from realikea.fidelity.meshes import load_pair
from realikea.fidelity.metric import DEFAULT_SAMPLES, surface_deviation
from realikea.files import repo_path

STATS = ("mean", "median", "p90")
REPORT_SEED = 0  # the report's default sampling seed


def report_csv(cfg: DictConfig | None = None) -> Path:
    """The parts.csv `realikea fidelity report` writes under `cfg`'s paths.fidelity_report (by
    default the default configuration's)."""
    cfg = cfg if cfg is not None else load_config()
    return repo_path(cfg.paths.fidelity_report) / "parts.csv"


def report_rows(path: Path) -> dict[str, dict[str, str]]:
    """A fidelity report's parts.csv rows by part id; none if the file does not exist."""
    if not Path(path).is_file():
        return {}
    with Path(path).open(newline="") as f:
        return {row["id"]: row for row in csv.DictReader(f)}


def fidelity_certificate(
    visual: Path,
    pieces: Sequence[Path],
    source: str,
    row: dict[str, str] | None,
    origin: str,
) -> dict:
    """The certificate of `pieces` (one collision source) against `visual`: from the report's
    `row` for the part (found at `origin`) if it counts the same meshes, else measured."""
    visual_mesh, piece_meshes = load_pair(visual, pieces)
    counts = {
        "visual_vertices": len(visual_mesh.vertices),
        "visual_faces": len(visual_mesh.faces),
        f"{source}_pieces": len(piece_meshes),
        f"{source}_vertices": sum(len(p.vertices) for p in piece_meshes),
        f"{source}_faces": sum(len(p.faces) for p in piece_meshes),
    }
    certificate: dict = {"source": source}
    if row is not None and all(int(row[k]) == v for k, v in counts.items()):
        for d in DIRECTIONS:
            certificate[f"{d}_m"] = {s: float(row[f"{source}_{d}_{s}_m"]) for s in STATS}
        certificate["origin"] = origin
        return certificate
    result = surface_deviation(visual_mesh, piece_meshes, samples=DEFAULT_SAMPLES, seed=REPORT_SEED)
    for d, deviation in zip(DIRECTIONS, (result.q_to_p, result.p_to_q), strict=True):
        certificate[f"{d}_m"] = {s: getattr(deviation, s) for s in STATS}
    certificate["origin"] = (
        f"measured at export (surface_deviation, {DEFAULT_SAMPLES} samples, seed {REPORT_SEED})"
    )
    return certificate
