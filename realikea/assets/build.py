"""Run the six steps over the library: parts through steps 1-4 (cached), configurations 5-6."""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from pathlib import Path

import trimesh
from omegaconf import DictConfig
from tqdm import tqdm

from realikea.assets import shapes
from realikea.assets.cache import cached_entry, link_or_copy
from realikea.assets.catalog import Configuration, Part, content_hash
from realikea.assets.workflow import (
    assembly,
    cleaning,
    clipping,
    collision,
    integration,
    segmentation,
)
from realikea.config import config_number
from realikea.errors import RealIkeaError
from realikea.files import atomic_write_text, staging_dir
from realikea.sim.resistance import nominal
from realikea.sources import model_name
from realikea.spawn import process_pool

PART_STEPS_VERSION = "2"  # bump when steps 1-4 change what they write
CONFIG_STEPS_VERSION = "5"  # bump when steps 5-6 change what they write
INDEX_COLUMNS = (
    "config_id",
    "part_id",
    "base_id",
    "category",
    "joint_type",
    "mjcf_coacd",
    "mjcf_hull",
)


@dataclass(frozen=True)
class WorkflowSettings:
    """The knobs of the workflow that change derived files (part of every cache key)."""

    coacd: collision.CoacdSettings
    mount_clearance: float
    front_clearance: float

    @classmethod
    def from_config(cls, cfg: DictConfig) -> WorkflowSettings:
        wf, c = cfg.workflow, cfg.workflow.coacd
        if c.preprocess not in ("auto", "on", "off"):
            raise RealIkeaError(f"workflow.coacd.preprocess={c.preprocess!r}: use auto, on or off")
        integers = ("preprocess_resolution", "resolution", "max_convex_hull")
        integers += ("mcts_iterations", "mcts_max_depth", "seed")
        coacd = collision.CoacdSettings(
            threshold=config_number(c, "threshold", "workflow.coacd.threshold", minimum=0.0),
            preprocess=c.preprocess,
            **{k: int(config_number(c, k, f"workflow.coacd.{k}")) for k in integers},
        )
        return cls(
            coacd,
            config_number(wf, "mount_clearance", "workflow.mount_clearance", minimum=0.0),
            config_number(wf, "front_clearance", "workflow.front_clearance", minimum=0.0),
        )


@dataclass(frozen=True)
class PartMeshes:
    """A part's cached step 1-4 results: the visual mesh and the pieces of each collision source."""

    key: str
    visual: Path
    pieces: dict[str, list[Path]]

    @classmethod
    def from_folder(cls, folder: Path) -> PartMeshes:
        meta = json.loads((folder / "meta.json").read_text())
        pieces = {src: [folder / f for f in files] for src, files in meta["pieces"].items()}
        return cls(folder.name, folder / meta["visual"], pieces)


def part_key(part: Part, settings: WorkflowSettings) -> str:
    """Cache key of a part's meshes: its data, the generators and the step 1-4 settings."""
    return content_hash(
        {
            "part": part.fingerprint(),
            "generator": shapes.GENERATOR_VERSION,
            "steps": PART_STEPS_VERSION,
            "coacd": asdict(settings.coacd),
            "mount_clearance": settings.mount_clearance,
        }
    )


def write_part_meshes(part: Part, settings: WorkflowSettings, folder: Path) -> None:
    """Steps 1-4 for one part, writing meshes and a meta.json into `folder`."""
    try:
        components = segmentation.formatted_components(part)  # step 1
        solid = cleaning.cleaned_solid(components)  # step 2
        clipped = clipping.clipped_for_collision(solid, settings.mount_clearance)  # step 3
        sources = {  # step 4
            "coacd": collision.coacd_pieces(clipped, settings.coacd),
            "hull": [collision.convex_hull(clipped)],
        }
    except RealIkeaError as err:
        raise RealIkeaError(f"part {part.id!r}: {err}") from err
    solid.export(folder / "visual.obj")
    pieces = {}
    for source, meshes in sources.items():
        pieces[source] = [f"{source}_{i:03d}.stl" for i in range(len(meshes))]
        for name, mesh in zip(pieces[source], meshes, strict=True):
            mesh.export(folder / name)
    meta = {
        "part_id": part.id,
        "visual": "visual.obj",
        "pieces": pieces,
        "visual_faces": len(solid.faces),
        "visual_vertices": len(solid.vertices),
        "watertight": bool(solid.is_watertight),
    }
    (folder / "meta.json").write_text(json.dumps(meta, indent=1))


def ensure_part(
    part: Part, settings: WorkflowSettings, cache_root: Path
) -> tuple[str, PartMeshes, bool]:
    """The part's cached meshes, built on a miss; returns (part id, meshes, built)."""
    key = part_key(part, settings)
    folder, built = cached_entry(
        cache_root / "parts", f"{part.id}-{key}", lambda d: write_part_meshes(part, settings, d)
    )
    return part.id, PartMeshes.from_folder(folder), built


def config_key(
    config: Configuration,
    meshes: PartMeshes,
    settings: WorkflowSettings,
    sources: tuple[str, ...],
) -> str:
    """Cache key of a configuration's folder: its part's meshes, base, friction, the nominal
    resistance its joint is written with, the front clearance and the collision sources."""
    return content_hash(
        {
            "part": meshes.key,
            "base": config.base.fingerprint(),
            "friction": config.part.friction,
            "resistance": asdict(nominal()),
            "front_clearance": settings.front_clearance,
            "sources": sources,
            "steps": CONFIG_STEPS_VERSION,
        }
    )


def is_current(folder: Path, key: str) -> bool:
    """Whether a configuration folder was built with exactly this key."""
    record = folder / "build.json"
    return record.is_file() and json.loads(record.read_text()).get("key") == key


def write_configuration(
    config: Configuration,
    meshes: PartMeshes,
    settings: WorkflowSettings,
    sources: tuple[str, ...],
    out_dir: Path,
) -> bool:
    """Steps 5-6 for one configuration into `out_dir/<config id>/`; False if already current."""
    folder = out_dir / config.id
    key = config_key(config, meshes, settings, sources)
    resistance = nominal()
    if is_current(folder, key):
        return False
    row = {
        "config_id": config.id,
        "part_id": config.part.id,
        "base_id": config.base.id,
        "category": config.part.category,
        "joint_type": config.base.joint,
    }
    handle = assembly.grasp_point(trimesh.load_mesh(meshes.visual))
    with staging_dir(folder) as tmp:
        link_or_copy(meshes.visual, tmp / "meshes" / "visual.obj")
        for source in sources:
            names = {}
            for i, piece in enumerate(meshes.pieces[source]):
                link_or_copy(piece, tmp / "meshes" / piece.name)
                names[f"part_{source}_{i:03d}"] = f"meshes/{piece.name}"
            unit = assembly.assemble(  # step 5
                config.part, config.base, names, "meshes/visual.obj", handle,
                resistance.damping, resistance.frictionloss, settings.front_clearance,
            )  # fmt: skip
            integration.write_mjcf(unit, tmp / model_name(source))  # step 6
            row[f"mjcf_{source}"] = f"{config.id}/{model_name(source)}"
        (tmp / "build.json").write_text(json.dumps({"key": key, "row": row}, indent=1))
    return True


@dataclass
class BuildReport:
    parts_built: int
    parts_cached: int
    configs_built: int
    configs_cached: int
    index: Path


def build_parts(
    parts: Iterable[Part],
    settings: WorkflowSettings,
    cache_root: Path,
    workers: int | None = None,
    progress: bool = True,
) -> tuple[dict[str, PartMeshes], int]:
    """Steps 1-4 for many parts in parallel; returns their meshes by id and how many were built."""
    parts = list({p.id: p for p in parts}.values())
    folders = {p.id: cache_root / "parts" / f"{p.id}-{part_key(p, settings)}" for p in parts}
    found = {pid: PartMeshes.from_folder(f) for pid, f in folders.items() if f.is_dir()}
    missing = [p for p in parts if p.id not in found]
    if not missing:  # no worker processes to start when everything is cached
        return found, 0
    with process_pool(workers or os.cpu_count() or 1) as pool:
        jobs = pool.map(
            ensure_part, missing, [settings] * len(missing), [cache_root] * len(missing)
        )
        done = list(tqdm(jobs, total=len(missing), desc="parts (steps 1-4)", disable=not progress))
    found.update({pid: meshes for pid, meshes, _ in done})
    return found, sum(built for *_, built in done)


def build_library(
    configs: Iterable[Configuration],
    settings: WorkflowSettings,
    sources: tuple[str, ...],
    cache_root: Path,
    out_dir: Path,
    workers: int | None = None,
    progress: bool = True,
) -> BuildReport:
    """Build configurations in parallel (parts first, then assembly) and rewrite index.csv.
    Every joint is written at the nominal resistance; a mode is applied by the scene or export."""
    configs = list({c.id: c for c in configs}.values())
    meshes, parts_built = build_parts(
        (c.part for c in configs), settings, cache_root, workers, progress
    )
    stale = [
        c
        for c in configs
        if not is_current(out_dir / c.id, config_key(c, meshes[c.part.id], settings, sources))
    ]
    if stale:
        with process_pool(workers or os.cpu_count() or 1) as pool:
            jobs = pool.map(
                write_configuration,
                stale,
                [meshes[c.part.id] for c in stale],
                [settings] * len(stale),
                [sources] * len(stale),
                [out_dir] * len(stale),
                chunksize=8,
            )
            desc = "configurations (steps 5-6)"
            list(tqdm(jobs, total=len(stale), desc=desc, disable=not progress))
    index = write_index(out_dir)
    n_built = len(stale)
    return BuildReport(
        parts_built, len(meshes) - parts_built, n_built, len(configs) - n_built, index
    )


def write_index(out_dir: Path) -> Path:
    """index.csv of every configuration folder under `out_dir` (written atomically). Another
    process's staging folders (`.<id>.<random>.tmp`, renamed into place when complete) are not
    configurations: reading one could race with its rename."""
    found = sorted(out_dir.glob("*/build.json"))
    rows = [json.loads(p.read_text())["row"] for p in found if not p.parent.name.startswith(".")]
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, INDEX_COLUMNS, restval="", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    atomic_write_text(out_dir / "index.csv", buffer.getvalue())
    return out_dir / "index.csv"
