"""The catalog as data: interactive parts and base units read from CSV, validated, combined."""

from __future__ import annotations

import csv
import hashlib
import json
import os
import textwrap
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

from realikea.assets.shapes import FAMILIES
from realikea.assets.split import SPLIT_FILE, check_split_value, read_split, suggest
from realikea.errors import RealIkeaError
from realikea.files import CATALOG_DIR, WORKSPACE

CATEGORIES = ("knob", "two_point", "finger_pull")
FRICTION_CLASSES = {
    "polished_metal": 0.4,
    "brushed_metal": 0.6,
    "plastic": 0.5,
    "wood": 0.6,
    "rubberized": 0.9,
}
BASE_KINDS = {"drawer": "slide", "door": "hinge", "flap": "hinge"}
SYNTHETIC_PREFIX = "syn_"  # the ids of synthetic parts (realikea/assets/synthetic.py)


def group_name(category: str, kind: str) -> str:
    """A category x kind group's name, as training logs it (`/success/<category>_<kind>`)."""
    return f"{category}_{kind}"


GROUPS = tuple(group_name(category, kind) for kind in BASE_KINDS for category in CATEGORIES)


def kind_and_category(group: str) -> tuple[str, str]:
    """A category x kind group's kind and category: ("door", "two_point") of "two_point_door"."""
    return next((k, c) for c in CATEGORIES for k in BASE_KINDS if group_name(c, k) == group)


def catalog_dir() -> Path:
    """The catalog folder (parts.csv, bases.csv, split.csv): `$REALIKEA_CATALOG` if set, else the
    package's own `realikea/catalog/`."""
    return Path(os.environ.get("REALIKEA_CATALOG", CATALOG_DIR))


def imported_dir(root: Path | None = None) -> Path:
    """Where imported parts live: `imported/` in an explicit catalog folder (`root` or
    `$REALIKEA_CATALOG`), else the workspace's `assets/imported/` (user data, not the package's)."""
    if root is None and "REALIKEA_CATALOG" not in os.environ:
        return WORKSPACE / "assets" / "imported"
    return (Path(root) if root is not None else catalog_dir()) / "imported"


def synthetic_dir(root: Path | None = None) -> Path:
    """Where synthetic parts live (`realikea.assets.synthetic`): `synthetic/` in an explicit
    catalog folder (`root` or `$REALIKEA_CATALOG`), else the workspace's
    `outputs/synthetic_parts/` (generated, outside git)."""
    if root is None and "REALIKEA_CATALOG" not in os.environ:
        return WORKSPACE / "outputs" / "synthetic_parts"
    return (Path(root) if root is not None else catalog_dir()) / "synthetic"


def content_hash(payload: object) -> str:
    """A stable short hash of JSON-serialisable data (the cache key of derived files)."""
    blob = json.dumps(payload, sort_keys=True, separators=(",", ":")).encode()
    return hashlib.sha256(blob).hexdigest()[:16]


@dataclass(frozen=True)
class Part:
    """One interactive part: a procedural family with dimensions, or an imported mesh."""

    id: str
    category: str
    family: str
    friction: str
    dims: dict[str, float] = field(default_factory=dict)
    mesh_file: Path | None = None  # set for imported parts: the formatted source mesh

    @property
    def friction_coefficient(self) -> float:
        return FRICTION_CLASSES[self.friction]

    def fingerprint(self) -> dict:
        """Everything the part's derived meshes depend on."""
        data = {"id": self.id, "family": self.family, "dims": self.dims}
        if self.mesh_file is not None:
            data["mesh_sha256"] = hashlib.sha256(self.mesh_file.read_bytes()).hexdigest()
        return data


@dataclass(frozen=True)
class Base:
    """One base furniture unit: a carcass and one moving front with its joint and mount."""

    id: str
    kind: str
    joint: str
    width: float
    height: float
    depth: float
    front_thickness: float
    reveal: float
    travel: float
    hinge: str
    mount_u: float
    mount_v: float
    mount_roll_deg: float

    def fingerprint(self) -> dict:
        return dict(self.__dict__)


@dataclass(frozen=True)
class Configuration:
    """One articulated configuration: a part mounted on a base's moving front."""

    part: Part
    base: Base

    @property
    def id(self) -> str:
        return f"{self.part.id}__{self.base.id}"

    @property
    def group(self) -> str:
        """Its category x kind group (`GROUPS`)."""
        return group_name(self.part.category, self.base.kind)


class Catalog:
    """All parts (catalog rows plus imported twins; synthetic parts by id) and bases, with lookups
    that name bad ids."""

    def __init__(
        self,
        parts: list[Part],
        bases: list[Base],
        split: dict[str, str] | None = None,
        synthetic: list[Part] = (),
    ):
        self.parts = {p.id: p for p in parts}
        # training-only parts past a family's sizes (realikea/assets/synthetic.py): resolved by
        # `part`, never in `parts`, a split or the catalog's count
        self.synthetic = {p.id: p for p in synthetic}
        self.bases = {b.id: b for b in bases}
        for kind, items, rows in (("part", self.parts, parts), ("base", self.bases, bases)):
            if len(items) != len(rows):
                seen: set[str] = set()
                dup = next(r.id for r in rows if r.id in seen or seen.add(r.id))
                raise RealIkeaError(f"duplicate {kind} id {dup!r} in the catalog")
        # {part id: train|test} from split.csv (realikea/assets/split.py); None without the file
        self.split = split

    @classmethod
    def load(cls, root: Path | None = None) -> Catalog:
        """Read `parts.csv`, `bases.csv` and `split.csv` of `root` (default `catalog_dir()`),
        every imported part (`imported_dir(root)`) and every synthetic part
        (`synthetic_dir(root)`)."""
        imported, made = imported_dir(root), synthetic_dir(root)
        root = Path(root) if root is not None else catalog_dir()
        parts = [_part_from_row(row, root / "parts.csv") for row in _rows(root / "parts.csv")]
        parts += [_imported_part(path) for path in sorted(imported.glob("*/part.json"))]
        bases = [_base_from_row(row, root / "bases.csv") for row in _rows(root / "bases.csv")]
        split_file = root / SPLIT_FILE
        split = read_split(split_file, parts) if split_file.is_file() else None
        synthetic = [
            _synthetic_part(path) for path in sorted(made.glob(f"{SYNTHETIC_PREFIX}*.json"))
        ]
        return cls(parts, bases, split, synthetic)

    def part(self, part_id: str) -> Part:
        if part_id in self.synthetic:
            return self.synthetic[part_id]
        if part_id not in self.parts:
            raise RealIkeaError(_unknown("part", part_id, self.parts))
        return self.parts[part_id]

    def base(self, base_id: str) -> Base:
        if base_id not in self.bases:
            raise RealIkeaError(_unknown("base", base_id, self.bases))
        return self.bases[base_id]

    def split_of(self, part_id: str) -> str:
        """train or test (split.csv; imported parts are test), or all without a split.csv."""
        self.part(part_id)
        return "all" if self.split is None else self.split[part_id]

    def parts_of_split(self, parts: list[Part], split: str) -> list[Part]:
        """The `parts` in `split` (train, test, or all)."""
        check_split_value(split)
        if split == "all":
            return parts
        if self.split is None:
            raise RealIkeaError(
                f"asset.split={split} needs a {SPLIT_FILE} beside the catalog's parts.csv; "
                "`realikea assets split --write` makes one (or use asset.split=all)"
            )
        return [p for p in parts if self.split[p.id] == split]

    def parts_in(self, category: str) -> list[Part]:
        """Parts of one category, or all of them for `all`."""
        if category != "all" and category not in CATEGORIES:
            raise RealIkeaError(
                f"unknown category {category!r}; choose one of {', '.join(CATEGORIES)} or all"
            )
        return [p for p in self.parts.values() if category in ("all", p.category)]

    def configurations(
        self,
        category: str = "all",
        part: str | None = None,
        base: str | None = None,
        kind: str | None = None,
        split: str = "all",
    ) -> Iterator[Configuration]:
        """Every part × base pair of a category, optionally pinned to one part and/or one base,
        or restricted to one kind of base (drawer, door, flap) and to the parts of one split
        (train, test or all; a pinned part is used whatever its split)."""
        if kind is not None and kind not in BASE_KINDS:
            raise RealIkeaError(
                f"unknown base kind {kind!r}; choose one of {', '.join(BASE_KINDS)}"
            )
        check_split_value(split)
        parts = [self.part(part)] if part else self.parts_of_split(self.parts_in(category), split)
        bases = [self.base(base)] if base else list(self.bases.values())
        bases = [b for b in bases if kind is None or b.kind == kind]
        for p in parts:
            for b in bases:
                yield Configuration(p, b)

    @cached_property
    def n_configurations(self) -> int:
        return len(self.parts) * len(self.bases)


def _unknown(kind: str, name: str, known) -> str:
    """'unknown part id 'x'; did you mean ...? known part ids (n): a, b, ...'"""
    listing = f"known {kind} ids ({len(known)}): {', '.join(sorted(known))}"
    wrapped = textwrap.fill(listing, width=100, subsequent_indent="  ", break_on_hyphens=False)
    return f"unknown {kind} id {name!r}{suggest(str(name), known)}\n{wrapped}"


def _rows(path: Path) -> list[dict[str, str]]:
    if not path.is_file():
        raise RealIkeaError(f"catalog file not found: {path}")
    with path.open(newline="") as f:
        return list(csv.DictReader(f))


def _number(value: str, column: str, row_id: str, path: Path) -> float:
    try:
        return float(value)
    except ValueError:
        raise RealIkeaError(
            f"{path}: {row_id}: column {column!r} is not a number: {value!r}"
        ) from None


def _check_common(row_id: str, category: str, friction: str, path: Path) -> None:
    if category not in CATEGORIES:
        raise RealIkeaError(
            f"{path}: {row_id}: unknown category {category!r}; "
            f"choose one of {', '.join(CATEGORIES)}"
        )
    if friction not in FRICTION_CLASSES:
        raise RealIkeaError(
            f"{path}: {row_id}: unknown friction class {friction!r}; "
            f"choose one of {', '.join(FRICTION_CLASSES)}"
        )


def _part_from_row(row: dict[str, str], path: Path) -> Part:
    pid, category, family, friction = (
        row[k].strip() for k in ("id", "category", "family", "friction")
    )
    _check_common(pid, category, friction, path)
    if family not in FAMILIES or FAMILIES[family].category != category:
        raise RealIkeaError(f"{path}: {pid}: unknown {category} family {family!r}")
    fixed = {"id", "category", "family", "friction"}
    dims = {k: _number(v, k, pid, path) for k, v in row.items() if k not in fixed and v.strip()}
    missing = [k for k in FAMILIES[family].dims if k not in dims]
    if missing:
        raise RealIkeaError(f"{path}: {pid}: family {family!r} needs dimensions {missing}")
    return Part(pid, category, family, friction, dims)


def _imported_part(path: Path) -> Part:
    meta = json.loads(path.read_text())
    _check_common(meta["id"], meta["category"], meta["friction"], path)
    return Part(
        meta["id"], meta["category"], "imported", meta["friction"], {}, path.parent / "mesh.ply"
    )


def _synthetic_part(path: Path) -> Part:
    meta = json.loads(path.read_text())
    _check_common(meta["id"], meta["category"], meta["friction"], path)
    if FAMILIES.get(meta["family"]) is None or not meta["id"].startswith(SYNTHETIC_PREFIX):
        raise RealIkeaError(f"{path}: not a synthetic part of a catalog family")
    return Part(meta["id"], meta["category"], meta["family"], meta["friction"], meta["dims"])


def _base_from_row(row: dict[str, str], path: Path) -> Base:
    bid = row["id"].strip()
    kind, joint, hinge = row["kind"].strip(), row["joint"].strip(), row["hinge"].strip()
    if BASE_KINDS.get(kind) != joint:
        raise RealIkeaError(f"{path}: {bid}: kind {kind!r} with joint {joint!r} is not supported")
    if (kind == "door") != (hinge in ("left", "right")) or (kind == "flap") != (hinge == "bottom"):
        raise RealIkeaError(f"{path}: {bid}: hinge {hinge!r} does not fit a {kind}")
    numbers = {
        k: _number(row[k], k, bid, path)
        for k in (
            "width", "height", "depth", "front_thickness", "reveal", "travel",
            "mount_u", "mount_v", "mount_roll_deg",
        )
    }  # fmt: skip
    return Base(bid, kind, joint, hinge=hinge, **numbers)


def effective_split(asset, catalog=None) -> str:
    """The split an `asset` config draws from: asset.split (all for configs written before the
    split existed), or, with asset.part pinned, that part's own split."""
    if asset.get("part"):
        catalog = catalog or Catalog.load()
        return catalog.split_of(str(asset.part))
    return str(asset.get("split", "all"))
