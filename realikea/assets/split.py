"""The held-out split of the catalog: which parts policies train on and which they are tested on.

`realikea/catalog/split.csv` (columns `part,split`, split = train or test) names every row of
`realikea/catalog/parts.csv`. Parts it does not name, i.e. parts imported under
`assets/imported/`, belong to `test`: no policy is trained on them. The `asset` group draws
from one split (`asset.split=train|test|all`, default train); `asset.part=ID` pins a part
whatever its split.

The file is generated, not hand-picked: `realikea assets split --write` (or
`write_split(catalog_dir() / SPLIT_FILE, make_split(parts))`) regenerates it from `parts.csv`
with `SEED`. See `make_split` for how the held-out parts are chosen.
"""

from __future__ import annotations

import csv
import io
import random
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Protocol

from realikea.config import overrides_set
from realikea.errors import RealIkeaError
from realikea.files import atomic_write_text


class Part(Protocol):
    """What the split reads of a catalog part (`realikea.assets.catalog.Part` is one; read-only,
    as that frozen dataclass's fields are)."""

    @property
    def id(self) -> str: ...
    @property
    def family(self) -> str: ...
    @property
    def dims(self) -> dict[str, float]: ...


SPLIT_FILE = "split.csv"
SPLITS = ("train", "test", "all")
SEED = 0
TEST_SHARE = 0.2  # about one part in five of every family is held out
# the dimension that orders a family by size: the first of these the family has
# (knobs: head diameter or width; bars and pulls: length; d/u handles and bows: hole spacing)
MAIN_DIMENSIONS = ("diameter", "width", "length", "cc")
IMPORTED = "imported"  # the family of imported parts: never in split.csv unless named there


def check_split_value(split: object) -> str:
    """`split` if it is one of SPLITS, else an error naming it and the options."""
    if split not in SPLITS:
        raise RealIkeaError(f"unknown asset.split {split!r}; choose one of {', '.join(SPLITS)}")
    return str(split)


def main_dimension(part: Part) -> float:
    """The size that orders a part within its family (see MAIN_DIMENSIONS)."""
    for key in MAIN_DIMENSIONS:
        if key in part.dims:
            return part.dims[key]
    raise RealIkeaError(
        f"part {part.id!r} (family {part.family!r}) has none of {', '.join(MAIN_DIMENSIONS)}"
    )


def held_out_count(n: int) -> int:
    """Parts held out of a family of `n`: round(n/5), at least 1, and fewer than half."""
    if n < 3:
        raise RealIkeaError(f"a family of {n} parts is too small to hold one out and keep most")
    return min(max(1, int(n * TEST_SHARE + 0.5)), (n - 1) // 2)


def make_split(parts: Iterable[Part], seed: int = SEED) -> dict[str, str]:
    """{part id: train|test} for catalog parts (imported parts are skipped: they are test).

    Stratified by family, spread over each family's size range: a family of n parts is sorted
    by its main dimension (then id), and k = round(n/5) parts are held out at evenly spaced
    positions floor(offset + i * n/k), i < k, with offset drawn uniformly from [0, n/k) by a
    generator seeded with (seed, family). So a family with two held-out parts gives one from
    its smaller and one from its larger half, and the single held-out part of a small family
    may fall anywhere in its range. Deterministic for a given catalog and seed.
    """
    families: dict[str, list[Part]] = {}
    for p in parts:
        if p.family != IMPORTED:
            families.setdefault(p.family, []).append(p)
    split: dict[str, str] = {}
    for family, members in families.items():
        ordered = sorted(members, key=lambda p: (main_dimension(p), p.id))
        n = len(ordered)
        k = held_out_count(n)
        stride = n / k
        offset = random.Random(f"{seed}/{family}").random() * stride
        test = {int(offset + i * stride) for i in range(k)}
        for i, p in enumerate(ordered):
            split[p.id] = "test" if i in test else "train"
    # catalog order, so the file diffs row by row against parts.csv
    return {p: split[p] for p in (q.id for fam in families.values() for q in fam)}


def split_text(split: dict[str, str]) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["part", "split"])
    writer.writerows(split.items())
    return out.getvalue()


def write_split(path: Path, split: dict[str, str]) -> Path:
    atomic_write_text(Path(path), split_text(split))
    return Path(path)


def read_split(path: Path, parts: Sequence[Part]) -> dict[str, str]:
    """{part id: train|test} from `path`, checked against the catalog's `parts`.

    Every row must name a known part once with split train or test; every catalog (non-imported)
    part must have a row; every family must keep a train part. Imported parts without a row are
    test.
    """
    path = Path(path)
    known = {p.id: p for p in parts}
    with path.open(newline="") as f:
        reader = csv.DictReader(f)
        if reader.fieldnames is None or not {"part", "split"} <= set(reader.fieldnames):
            raise RealIkeaError(f"{path}: the header must have columns part,split")
        split: dict[str, str] = {}
        for row in reader:
            where = f"{path}: line {reader.line_num}"
            pid, value = (row.get("part") or "").strip(), (row.get("split") or "").strip()
            if pid not in known:
                raise RealIkeaError(f"{where}: unknown part {pid!r}{suggest(pid, known)}")
            if value not in ("train", "test"):
                raise RealIkeaError(f"{where}: part {pid!r} has split {value!r}; use train or test")
            if pid in split:
                raise RealIkeaError(f"{where}: part {pid!r} is listed twice")
            split[pid] = value
    missing = [p.id for p in parts if p.family != IMPORTED and p.id not in split]
    if missing:
        raise RealIkeaError(
            f"{path}: no row for catalog part(s) {', '.join(missing)}; "
            "`realikea assets split --write` regenerates the file"
        )
    for p in parts:
        split.setdefault(p.id, "test")  # imported parts: never trained on
    trained = {p.family for p in parts if split[p.id] == "train"}
    untrained = sorted({p.family for p in parts if p.family != IMPORTED} - trained)
    if untrained:
        raise RealIkeaError(f"{path}: family {', '.join(untrained)} has no train part")
    return split


def suggest(name: str, options: Iterable[str]) -> str:
    """'; did you mean a, b?' for close matches of `name` among `options`, else ''."""
    import difflib

    close = difflib.get_close_matches(name, list(options), n=3, cutoff=0.6)
    return f"; did you mean {', '.join(close)}?" if close else ""


def with_default_split(overrides: Sequence[str], split: str = "test") -> list[str]:
    """`overrides` plus `asset.split=<split>` unless they set asset.split themselves (the
    evaluation commands default to the held-out parts)."""
    check_split_value(split)
    if overrides_set(overrides, "asset.split"):
        return list(overrides)
    return [*overrides, f"asset.split={split}"]
