"""Export many built configurations into one format: check the request, then write each
configuration into a staging folder renamed into place, skipping those already complete and
current.
Each model carries one resistance mode, applied here to the library's nominal joint.

Layout: `OUT/<format>_<collision>/<config id>/` holds `model_<collision>.urdf|.usd|.xml`, the
meshes it references (URDF, MJCF; USD stores them in the file) and `metadata.json`, whose
`export.key` says what it was made from: a rerun skips a folder whose key matches.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path

from tqdm import tqdm

from realikea.assets.catalog import Configuration, content_hash
from realikea.errors import RealIkeaError
from realikea.export import mjcf, urdf, usd
from realikea.export.metadata import PART_LINK, configuration_metadata
from realikea.export.model import Articulation, read_articulation, with_resistance
from realikea.fidelity.certificate import fidelity_certificate, report_csv, report_rows
from realikea.files import shown_path, staging_dir
from realikea.sim.resistance import Resistance, modes, nominal
from realikea.sources import check_source, model_name, model_path

EXPORT_VERSION = "1"  # bump when an exporter or metadata.json changes what it writes
LISTED = 5  # configurations named in an error before "and n more"


@dataclass(frozen=True)
class Exporter:
    """One format: its writer, its model file's suffix and how it carries joint resistance."""

    write: Callable[[Articulation, Path, str], Path]
    suffix: str
    resistance_schema: str


EXPORTERS = {
    "urdf": Exporter(urdf.write_urdf, ".urdf", urdf.RESISTANCE_SCHEMA),
    "usd": Exporter(usd.write_usd, ".usd", usd.RESISTANCE_SCHEMA),
    "mjcf": Exporter(mjcf.write_mjcf, ".xml", mjcf.RESISTANCE_SCHEMA),
}


@dataclass(frozen=True)
class ExportReport:
    """What one export run did, and where."""

    exported: int
    current: int
    folder: Path


def export_folder(out: Path, fmt: str, source: str, config_id: str) -> Path:
    """Where one configuration's export goes."""
    return Path(out) / f"{fmt}_{source}" / config_id


def _not_built(configs: Sequence[Configuration], library: Path, source: str) -> list[str]:
    """Ids of the configurations without a built folder for `source` in `library`."""
    return [
        c.id
        for c in configs
        if not (library / c.id / "build.json").is_file()
        or not model_path(library, c.id, source).is_file()
    ]


def check_request(
    configs: Sequence[Configuration], fmt: str, source: str, library: Path, out: Path
) -> None:
    """Refuse, before anything is written, an unknown format or source, an `out` that is a file,
    no configuration, or configurations not built (naming them and how to build them)."""
    if fmt not in EXPORTERS:
        raise RealIkeaError(f"unknown export format {fmt!r}; choose one of {', '.join(EXPORTERS)}")
    check_source(source)
    if Path(out).exists() and not Path(out).is_dir():
        raise RealIkeaError(f"--out {out} is an existing file; give a folder")
    if not configs:
        raise RealIkeaError("no configuration selected to export")
    missing = _not_built(configs, library, source)
    if missing:
        by_id = {c.id: c for c in configs}
        lines = [
            f"  {cid}: realikea assets build --part {by_id[cid].part.id} "
            f"--base {by_id[cid].base.id} paths.library={library}"
            for cid in missing[:LISTED]
        ]
        more = f"\n  ... and {len(missing) - LISTED} more" if len(missing) > LISTED else ""
        raise RealIkeaError(
            f"{len(missing)} of {len(configs)} configurations are not built for {source} in "
            f"{library}; build them first:\n" + "\n".join(lines) + more
        )


def _digest(paths: Sequence[Path]) -> str:
    """A content hash of mesh files (the same part's meshes in every configuration folder)."""
    sha = hashlib.sha256()
    for path in paths:
        sha.update(path.read_bytes())
    return sha.hexdigest()


def is_current(folder: Path, key: str) -> bool:
    """Whether an export folder is complete (it exists only once renamed) and made with `key`."""
    record = folder / "metadata.json"
    return record.is_file() and json.loads(record.read_text())["export"]["key"] == key


def export_configurations(
    configs: Sequence[Configuration],
    fmt: str,
    source: str,
    library: Path,
    out: Path,
    *,
    resistance: Resistance | None = None,
    fidelity_csv: Path | None = None,
    progress: bool = True,
) -> ExportReport:
    """Export `configs` built in `library` as `fmt` with collision `source` under `out`, their
    joints at `resistance` (default: the nominal mode)."""
    library, out = Path(library), Path(out)
    check_request(configs, fmt, source, library, out)
    exporter = EXPORTERS[fmt]
    fidelity_csv = Path(fidelity_csv) if fidelity_csv is not None else report_csv()
    rows = report_rows(fidelity_csv)
    resistance = resistance or nominal()
    every_mode = modes()
    certificates: dict[str, dict] = {}  # by the meshes' digest: once per part
    exported = 0
    bar = tqdm(configs, desc=f"export {fmt} ({source})", disable=not progress or len(configs) < 2)
    for config in bar:
        built = library / config.id
        build_key = json.loads((built / "build.json").read_text())["key"]
        key = content_hash(
            {
                "build": build_key,
                "format": fmt,
                "source": source,
                "version": EXPORT_VERSION,
                "modes": [asdict(m) for m in every_mode],
                "resistance": asdict(resistance),
                "fidelity": rows.get(config.part.id),
            }
        )
        folder = export_folder(out, fmt, source, config.id)
        if is_current(folder, key):
            continue
        articulation = with_resistance(read_articulation(built / model_name(source)), resistance)
        part = articulation.link(PART_LINK)
        visual = next(s.mesh for s in part.shapes if s.visual and s.mesh is not None)
        pieces = [s.mesh for s in part.shapes if s.collides]
        digest = _digest([visual, *pieces])
        if digest not in certificates:
            row = rows.get(config.part.id)
            certificates[digest] = fidelity_certificate(
                visual, pieces, source, row, shown_path(fidelity_csv)
            )
        name = model_name(source, exporter.suffix)
        with staging_dir(folder) as tmp:
            exporter.write(articulation, tmp, name)
            export = {
                "format": fmt,
                "collision": source,
                "model": name,
                "files": sorted(
                    p.relative_to(tmp).as_posix() for p in tmp.rglob("*") if p.is_file()
                ),
                "resistance_schema": exporter.resistance_schema,
                "key": key,
                "build_key": build_key,
            }
            metadata = configuration_metadata(
                config,
                articulation,
                visual,
                every_mode,
                resistance.name,
                certificates[digest],
                export,
            )
            (tmp / "metadata.json").write_text(json.dumps(metadata, indent=1) + "\n")
        exported += 1
    return ExportReport(exported, len(configs) - exported, out / f"{fmt}_{source}")
