"""Synthetic parts: a procedural family continued past the sizes its catalog parts span.

Every catalog part is a family and its dimensions (`realikea/catalog/parts.csv`), so a family can
make parts at sizes it has none of. `size_law_parts` takes the parts a policy trains on and, for
each family among them, makes `per_family` parts whose main dimension (`split.main_dimension`) is
log-spaced from `span[0]` times the family's smallest to `span[1]` times its largest, ends
included; every other dimension comes from a straight-line fit of that dimension on the main one
over the family's parts (its own size law, continued past its ends), kept at or above half the
family's smallest value of it so that no wall or rod thins to nothing; a size whose dimensions
the family's own rules refuse (a bar's posts past its ends) is left out and named. The friction
class is the nearest part's. A synthetic part is training-only: no split names it and no
evaluation draws it.

Ids are `syn_<family>_<main dimension in 0.1 mm>_<hash of the dimensions>`, so two laws that
make different parts never share an id. `write_synthetic` stores each part as one JSON file
(`catalog.synthetic_dir()`, generated, outside git) that `Catalog.load` reads back, so every process
(the env pool's workers, an evaluation) resolves the id as the catalog's own parts.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from realikea.assets.catalog import SYNTHETIC_PREFIX, Part, content_hash
from realikea.assets.shapes import part_mesh
from realikea.assets.split import MAIN_DIMENSIONS, main_dimension
from realikea.errors import RealIkeaError
from realikea.files import atomic_write_text

FLOOR = 0.5  # a fitted dimension stays at or above this share of the family's smallest value


def check_spec(spec) -> tuple[tuple[float, float], int]:
    """`asset.synthetic`'s (span, per_family), or an error naming the bad value."""
    if not isinstance(spec, Mapping):
        raise RealIkeaError(
            f"asset.synthetic={spec!r}: use null or {{span: [low, high], per_family: N}}"
        )
    span, per_family = spec.get("span"), spec.get("per_family")
    if (
        not isinstance(span, Sequence)
        or len(span) != 2
        or not all(isinstance(x, int | float) and not isinstance(x, bool) for x in span)
        or not 0 < span[0] <= 1 <= span[1]
    ):
        raise RealIkeaError(
            f"asset.synthetic.span={span!r}: use [low, high] with 0 < low <= 1 <= high "
            "(multiples of a family's smallest and largest main dimension)"
        )
    if isinstance(per_family, bool) or not isinstance(per_family, int) or per_family < 2:
        raise RealIkeaError(f"asset.synthetic.per_family={per_family!r}: use a whole number >= 2")
    return (float(span[0]), float(span[1])), per_family


def main_key(part: Part) -> str:
    """The name of the part's main dimension (`split.main_dimension`'s)."""
    main_dimension(part)  # names the part if it has none
    return next(k for k in MAIN_DIMENSIONS if k in part.dims)


def size_law(members: list[Part], key: str, name: str) -> tuple[np.ndarray, float]:
    """Dimension `name` of a family on its main dimension `key`: the straight-line fit over the
    parts that have it (their mean where they share one size) and its floor."""
    xs, ys = np.array([(p.dims[key], p.dims[name]) for p in members if name in p.dims]).T
    fit = np.polyfit(xs, ys, 1) if len(set(xs)) > 1 else np.array([0.0, ys.mean()])
    return fit, FLOOR * float(ys.min())


def size_law_parts(
    parts: list[Part], span: tuple[float, float], per_family: int
) -> tuple[list[Part], list[str]]:
    """`per_family` synthetic parts of each family of `parts` (see the module docstring), less
    those whose dimensions the family's own rules refuse (`part_mesh`), and why each was."""
    families: dict[str, list] = {}
    for p in parts:
        if p.family != "imported":
            families.setdefault(p.family, []).append(p)
    made, refused = [], []
    for family, members in sorted(families.items()):
        key = main_key(members[0])
        x = np.array([p.dims[key] for p in members])
        names = sorted({k for p in members for k in p.dims} - {key})
        laws = {name: size_law(members, key, name) for name in names}  # once a family
        for size in np.geomspace(span[0] * x.min(), span[1] * x.max(), per_family):
            dims = {key: round(float(size), 5)}
            for name, (fit, floor) in laws.items():
                dims[name] = round(max(float(np.polyval(fit, size)), floor), 5)
            nearest = min(members, key=lambda p: abs(np.log(p.dims[key] / size)))
            pid = f"{SYNTHETIC_PREFIX}{family}_{round(size * 1e4)}_{content_hash(dims)[:6]}"
            try:
                part_mesh(family, dims)
            except RealIkeaError as err:
                refused.append(f"{pid}: {err}")
                continue
            made.append(Part(pid, nearest.category, family, nearest.friction, dims))
    return made, refused


def write_synthetic(parts: list[Part], folder: Path) -> None:
    """Each part as `folder/<id>.json` (atomic; the same id always holds the same part)."""
    for p in parts:
        meta = {"id": p.id, "category": p.category, "family": p.family}
        meta |= {"friction": p.friction, "dims": p.dims}
        atomic_write_text(Path(folder) / f"{p.id}.json", json.dumps(meta, sort_keys=True) + "\n")
