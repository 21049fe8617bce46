"""`realikea assets release`: the whole library in every format and collision source, with the
dataset card and a manifest of every file's size and SHA-256.

Layout of OUT: `DATASET.md` (the repository's dataset card, copied), `manifest.json`, and
`<format>_<collision>/<config id>/` as `realikea assets export` writes them (export/driver.py).
The exports are resumable and cached: a rerun re-exports only configurations whose export key
changed, and a configuration folder appears only once complete. The manifest is removed before
anything is exported and written last, atomically: a manifest in OUT always describes the
folders beside it, and an interrupted release leaves none. It holds no time stamp, so a rerun
over unchanged folders rewrites it byte for byte. `verification.json` (`--verify`,
export/verify.py) is written after it and, like it, removed when a release starts.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from tqdm import tqdm

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, Catalog, Configuration
from realikea.errors import RealIkeaError
from realikea.export import FORMATS
from realikea.export.driver import (
    EXPORT_VERSION,
    LISTED,
    check_request,
    export_configurations,
    export_folder,
)
from realikea.files import CATALOG_DIR, atomic_path, atomic_write_text, repo_path
from realikea.sim.resistance import MODES, Resistance
from realikea.sources import SOURCES

CARD = "DATASET.md"  # the dataset card, at the repository root and in every release
MANIFEST = "manifest.json"
VERIFICATION = "verification.json"  # written beside the manifest by `--verify` (export/verify.py)
MANIFEST_VERSION = "1"  # bump when the manifest's layout changes
DATASET = "Real-IKEA"
CHUNK = 1 << 20  # bytes read at a time when hashing


@dataclass(frozen=True)
class ReleaseReport:
    """What one release run did: configurations exported and up to date per folder
    (`<format>_<collision>`), the totals the manifest records, and where it is."""

    exported: dict[str, int]
    current: dict[str, int]
    files: int
    bytes: int
    manifest: Path
    unlisted: list[str]


def library_configurations() -> list[Configuration]:
    """What a release ships: every part x base configuration of the catalog (its rows and any
    imported parts), as `realikea assets export --all` selects them."""
    return list(Catalog.load().configurations())


def catalog_counts(catalog: Catalog | None = None) -> dict:
    """The counts DATASET.md quotes (its YAML header's `counts`), from the catalog shipped with
    the package (`realikea/catalog/`, no imported parts) unless a catalog is given; printed by
    `realikea assets release --counts`."""
    catalog = catalog if catalog is not None else Catalog.load(CATALOG_DIR)
    bases = list(catalog.bases.values())
    families: dict[str, int] = {}
    for part in catalog.parts.values():
        families[part.family] = families.get(part.family, 0) + 1
    splits = {s: sum(catalog.split_of(p) == s for p in catalog.parts) for s in ("train", "test")}
    return {
        "parts": len(catalog.parts),
        "parts_per_category": {c: len(catalog.parts_in(c)) for c in CATEGORIES},
        "parts_per_family": families,
        "parts_per_split": splits if catalog.split is not None else None,
        "bases": len(bases),
        "bases_per_kind": {k: sum(b.kind == k for b in bases) for k in BASE_KINDS},
        "configurations": catalog.n_configurations,
        "collision_sources": list(SOURCES),
        "resistance_modes": list(MODES),
        "formats": list(FORMATS),
        "model_folders": catalog.n_configurations * len(SOURCES) * len(FORMATS),
    }


def _unique(values: Sequence[str]) -> list[str]:
    """`values` without repeats, in their first order."""
    return list(dict.fromkeys(values))


def check_release(
    configs: Sequence[Configuration],
    formats: Sequence[str],
    sources: Sequence[str],
    library: Path,
    out: Path,
    card: Path,
) -> None:
    """Refuse, before anything is written, what the export itself refuses for any format and
    source (an unknown one, an `out` that is a file, no configuration, configurations not built),
    no format or source at all, and a missing dataset card."""
    if not formats:
        raise RealIkeaError(f"no format to release; choose from {', '.join(FORMATS)}")
    if not sources:
        raise RealIkeaError(f"no collision source to release; choose from {', '.join(SOURCES)}")
    for fmt in formats:
        for source in sources:
            check_request(configs, fmt, source, library, out)
    if not Path(card).is_file():
        raise RealIkeaError(f"the dataset card {card} does not exist; a release ships it")


def sha256_file(path: Path) -> str:
    """The SHA-256 of a file's bytes, read in chunks."""
    sha = hashlib.sha256()
    with Path(path).open("rb") as f:
        while chunk := f.read(CHUNK):
            sha.update(chunk)
    return sha.hexdigest()


class Hasher:
    """File entries (relative path, size, SHA-256), each distinct file hashed once a run: the
    library's meshes are hard links of one cache file, shared by a part's 13 configurations."""

    def __init__(self, root: Path):
        """Entries relative to `root`, the release folder."""
        self.root = Path(root)
        self.digests: dict[tuple[int, int, int, int], str] = {}

    def entry(self, path: Path) -> dict:
        """{"path": POSIX path relative to the release root, "size": bytes, "sha256": hex}."""
        stat = path.stat()
        inode = (stat.st_dev, stat.st_ino, stat.st_size, stat.st_mtime_ns)
        if inode not in self.digests:
            self.digests[inode] = sha256_file(path)
        relative = path.relative_to(self.root).as_posix()
        return {"path": relative, "size": stat.st_size, "sha256": self.digests[inode]}


def _folder_files(folder: Path, metadata: dict) -> tuple[list[Path], str | None]:
    """The files of an export folder, sorted, and what is wrong with it if it does not hold
    exactly what its metadata.json lists (a folder changed after its export)."""
    present = sorted(p for p in folder.rglob("*") if p.is_file())
    names = {p.relative_to(folder).as_posix() for p in present}
    expected = {*metadata["export"]["files"], "metadata.json"}
    if names == expected:
        return present, None
    missing, extra = sorted(expected - names), sorted(names - expected)
    problem = "; ".join(
        f"{what} {', '.join(items[:LISTED])}"
        for what, items in (("missing", missing), ("not from the export", extra))
        if items
    )
    return present, problem


def _same(record: dict, key: str, value, config_id: str, what: str) -> None:
    """Set `record[key]` to `value`, refusing a value that differs between a configuration's
    folders (exported from one build, they cannot unless a folder was edited)."""
    if record.setdefault(key, value) != value:
        raise RealIkeaError(
            f"{config_id}: its export folders disagree on {what}; delete them and release again"
        )


def _config_entry(config, folders: dict, out: Path, hasher, totals: dict, broken: list) -> dict:
    """One configuration's manifest entry: its ids, resistance mode, certificate per source and
    every file of its export folders (adding to `totals`; a folder that does not hold what its
    metadata lists goes to `broken`)."""
    record: dict = {
        "part_id": config.part.id,
        "base_id": config.base.id,
        "category": config.part.category,
        "family": config.part.family,
        "kind": config.base.kind,
    }
    certificates: dict[str, dict] = {}
    exports: dict[str, dict] = {}
    for name, (fmt, source) in folders.items():
        folder = export_folder(out, fmt, source, config.id)
        metadata = json.loads((folder / "metadata.json").read_text())
        files, problem = _folder_files(folder, metadata)
        if problem:
            broken.append(f"{folder}: {problem}")
        mode = metadata["resistance"]["exported"]["mode"]
        _same(record, "resistance_mode", mode, config.id, "the resistance mode")
        certificate = metadata["fidelity_certificate"]
        _same(certificates, source, certificate, config.id, f"the {source} certificate")
        listed = [hasher.entry(p) for p in files]
        exports[name] = {
            "format": fmt,
            "collision": source,
            "model": (folder / metadata["export"]["model"]).relative_to(out).as_posix(),
            "files": listed,
        }
        totals[name]["configurations"] += 1
        totals[name]["files"] += len(listed)
        totals[name]["bytes"] += sum(e["size"] for e in listed)
    return {**record, "fidelity_certificate": certificates, "exports": exports}


def build_manifest(
    configs: Sequence[Configuration],
    formats: Sequence[str],
    sources: Sequence[str],
    out: Path,
    *,
    progress: bool = True,
) -> dict:
    """The manifest of a release folder: the release-level files (the card) and, per
    configuration, its ids, the resistance mode its models carry, its fidelity
    certificate per collision source and every file of every export folder; with totals of
    files and bytes (the manifest itself excluded) and per folder."""
    out = Path(out)
    hasher = Hasher(out)
    folders = {f"{fmt}_{source}": (fmt, source) for fmt in formats for source in sources}
    totals = {
        name: {"format": fmt, "collision": source, "configurations": 0, "files": 0, "bytes": 0}
        for name, (fmt, source) in folders.items()
    }
    entries: dict[str, dict] = {}
    broken: list[str] = []
    bar = tqdm(
        total=len(configs) * len(folders),
        desc="manifest",
        disable=not progress or len(configs) < 2,
    )
    for config in configs:
        entries[config.id] = _config_entry(config, folders, out, hasher, totals, broken)
        bar.update(len(folders))
    bar.close()
    if broken:
        more = f"\n  ... and {len(broken) - LISTED} more" if len(broken) > LISTED else ""
        raise RealIkeaError(
            f"{len(broken)} export folders do not hold what their metadata.json lists; delete "
            "them and release again:\n  " + "\n  ".join(broken[:LISTED]) + more
        )
    release_files = [hasher.entry(out / CARD)]
    return {
        "dataset": DATASET,
        "manifest_version": MANIFEST_VERSION,
        "export_version": EXPORT_VERSION,
        "formats": list(formats),
        "collision_sources": list(sources),
        "checksum": "sha256",
        "paths": "POSIX, relative to the folder holding this manifest",
        "totals": {
            "configurations": len(entries),
            "files": len(release_files) + sum(t["files"] for t in totals.values()),
            "bytes": sum(e["size"] for e in release_files)
            + sum(t["bytes"] for t in totals.values()),
            "folders": totals,
            "excludes": MANIFEST,
        },
        "files": release_files,
        "configurations": entries,
    }


def _copy_card(card: Path, out: Path) -> None:
    """Copy the dataset card into the release atomically, leaving an identical copy untouched."""
    target = out / CARD
    data = Path(card).read_bytes()
    if target.is_file() and target.read_bytes() == data:
        return
    with atomic_path(target) as tmp:
        tmp.write_bytes(data)


def unlisted_entries(
    configs: Sequence[Configuration], formats: Sequence[str], sources: Sequence[str], out: Path
) -> list[str]:
    """What OUT holds beside the release (other configurations' folders, other folders, staging
    left by a killed process), relative to OUT: the manifest does not list them."""
    out = Path(out)
    names = {f"{fmt}_{source}" for fmt in formats for source in sources}
    ids = {c.id for c in configs}
    extra = [
        p.name
        for p in sorted(out.iterdir())
        if p.name not in names | {CARD, MANIFEST, VERIFICATION}
    ]
    for name in sorted(names):
        extra += [f"{name}/{p.name}" for p in sorted((out / name).iterdir()) if p.name not in ids]
    return extra


def release_library(
    configs: Sequence[Configuration],
    library: Path,
    out: Path,
    formats: Sequence[str] = FORMATS,
    sources: Sequence[str] = SOURCES,
    *,
    resistance: Resistance | None = None,
    card: Path | None = None,
    fidelity_csv: Path | None = None,
    progress: bool = True,
) -> ReleaseReport:
    """Export `configs` built in `library` in every format of `formats` with every collision
    source of `sources` under `out`, their joints at `resistance` (default: the nominal mode),
    copy the dataset card in and write the manifest last."""
    library, out = Path(library), Path(out)
    formats, sources = _unique(formats), _unique(sources)
    card = Path(card) if card is not None else repo_path(CARD)
    check_release(configs, formats, sources, library, out, card)
    manifest = out / MANIFEST
    manifest.unlink(missing_ok=True)  # stale from here on, until rewritten at the end
    (out / VERIFICATION).unlink(missing_ok=True)  # verified the folders about to change
    out.mkdir(parents=True, exist_ok=True)
    exported, current = {}, {}
    pairs = [(fmt, source) for fmt in formats for source in sources]
    for fmt, source in tqdm(pairs, desc="release", disable=not progress):
        report = export_configurations(
            configs,
            fmt,
            source,
            library,
            out,
            resistance=resistance,
            fidelity_csv=fidelity_csv,
            progress=progress,
        )
        exported[f"{fmt}_{source}"], current[f"{fmt}_{source}"] = report.exported, report.current
    _copy_card(card, out)
    record = build_manifest(configs, formats, sources, out, progress=progress)
    atomic_write_text(manifest, json.dumps(record, indent=1) + "\n")
    return ReleaseReport(
        exported,
        current,
        record["totals"]["files"],
        record["totals"]["bytes"],
        manifest,
        unlisted_entries(configs, formats, sources, out),
    )
