"""Read a built library: its index, one configuration's MuJoCo model, a training draw."""

from __future__ import annotations

import csv
import sys
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from realikea.assets.build import WorkflowSettings, build_library
from realikea.assets.catalog import Catalog, Configuration, synthetic_dir
from realikea.assets.synthetic import check_spec, size_law_parts, write_synthetic
from realikea.errors import RealIkeaError
from realikea.files import repo_path
from realikea.sources import SOURCES, model_path

FRONT_JOINT = "front_joint"


def read_index(library: Path) -> list[dict[str, str]]:
    """The rows of `index.csv`, one per configuration."""
    index = Path(library) / "index.csv"
    if not index.is_file():
        raise RealIkeaError(f"no index.csv in {library}; run `realikea assets build` first")
    with index.open(newline="") as f:
        return list(csv.DictReader(f))


HINGE_SIDES = (None, "left", "right")  # asset.hinge: any base, or only doors hinged on a side
# what `asset.stratify` may group configurations by
STRATA = {"category": lambda c: c.part.category, "kind": lambda c: c.base.kind}


def load_model(mjcf: Path) -> mujoco.MjModel:
    """Compile one built configuration as written (its joint at the nominal resistance)."""
    if not Path(mjcf).is_file():
        raise RealIkeaError(f"MJCF not found: {mjcf}")
    return mujoco.MjModel.from_xml_path(str(mjcf))


def turns(count: dict[tuple, int]) -> list[tuple]:
    """A draw's turns over its groups: each group once, in order, then again for every extra
    turn `count` gives it ({a: 2, b: 1}: a, b, a)."""
    return [
        label for r in range(max(count.values(), default=1)) for label in count if count[label] > r
    ]


def group_turns(labels: list[tuple], weights) -> list[tuple]:
    """The draw's turns when `weights` gives groups holding a value extra turns ({door: 2}: a
    group whose label holds `door` takes two turns for every one of the others), or one group by
    its name, its values joined by `_` ({two_point_door: 2} under stratify [category, kind]); a
    label's weight is the product of its values' and its name's."""
    weights = dict(weights or {})
    values = {v for label in labels for v in label} | {"_".join(label) for label in labels}
    bad = {
        k: w
        for k, w in weights.items()
        if k not in values or not isinstance(w, int) or isinstance(w, bool) or w < 1
    }
    if bad:
        raise RealIkeaError(
            f"asset.group_weights: {bad} is not a whole number >= 1 on a group value or name "
            f"of asset.stratify ({sorted(values)})"
        )
    weight = {label: np.prod([weights.get(v, 1) for v in (*label, "_".join(label))])
              for label in labels}  # fmt: skip
    return turns({label: int(w) for label, w in weight.items()})


@dataclass
class TrainingDraw:
    """The stratified draw: each group's candidates in the seeded order, the group and
    configuration of every env, and how many of each group's members were taken (a group's next
    configuration is the one after, cycling)."""

    keys: list[str]
    groups: dict[tuple, list[Configuration]]
    labels: list[tuple] = field(default_factory=list)
    configurations: list[Configuration] = field(default_factory=list)
    drawn: dict[tuple, int] = field(default_factory=dict)

    def take(self, label: tuple) -> Configuration:
        """The group's next configuration."""
        members = self.groups[label]
        k = self.drawn.get(label, 0)
        self.drawn[label] = k + 1
        return members[k % len(members)]


def withheld(catalog: Catalog, asset, candidates: list[Configuration]) -> set[str]:
    """`asset.withhold`'s part ids, each a catalog part the draw would otherwise hold, or an
    error naming those that are not."""
    ids = list(asset.get("withhold") or ())
    unknown = [p for p in ids if p not in catalog.parts]
    if unknown:
        raise RealIkeaError(f"asset.withhold: unknown part(s) {unknown}")
    drawn = {c.part.id for c in candidates}
    absent = [p for p in ids if p not in drawn]
    if absent:
        raise RealIkeaError(
            f"asset.withhold: {absent} not in the draw (asset.category={asset.category} "
            f"kind={asset.get('kind')} split={asset.get('split', 'all')})"
        )
    return set(ids)


def with_synthetic(asset, candidates: list[Configuration]) -> list[Configuration]:
    """The candidates and, with `asset.synthetic` ({span, per_family}), every synthetic part of
    their families (`realikea.assets.synthetic`) on each of their bases, stored for the env
    pool's workers to resolve."""
    spec = asset.get("synthetic")
    if spec is None:
        return candidates
    span, per_family = check_spec(spec)
    parts = list({c.part.id: c.part for c in candidates}.values())
    made, refused = size_law_parts(parts, span, per_family)
    for reason in refused:
        print(f"asset.synthetic: left out {reason}", file=sys.stderr, flush=True)
    write_synthetic(made, synthetic_dir())
    bases = list({c.base.id: c.base for c in candidates}.values())
    return candidates + [Configuration(p, b) for p in made for b in bases]


def training_draw(cfg, n: int, seed: int = 0) -> TrainingDraw:
    """`n` configurations of the `asset` group by the stratified draw (`training_configurations`
    says how), not yet built."""
    catalog = Catalog.load()
    asset = cfg.asset
    candidates = list(
        catalog.configurations(
            asset.category, asset.part, asset.base, asset.get("kind"), asset.get("split", "all")
        )
    )
    out = withheld(catalog, asset, candidates)
    hinge = asset.get("hinge")
    if hinge not in HINGE_SIDES:
        raise RealIkeaError(f"asset.hinge={hinge!r}: use null, left or right (a door's hinge side)")
    candidates = [c for c in candidates if hinge is None or c.base.hinge == hinge]
    candidates = with_synthetic(asset, [c for c in candidates if c.part.id not in out])
    if not candidates:
        raise RealIkeaError(
            f"no configuration matches asset.category={asset.category} part={asset.part} "
            f"base={asset.base} kind={asset.get('kind')} hinge={hinge} "
            f"split={asset.get('split', 'all')}"
        )
    keys = list(asset.get("stratify") or ())
    unknown = [k for k in keys if k not in STRATA]
    if unknown:
        raise RealIkeaError(f"asset.stratify: unknown key(s) {unknown}; use {sorted(STRATA)}")
    order = np.random.default_rng(seed).permutation(len(candidates))
    groups: dict[tuple, list] = {}  # in the order the seeded permutation meets them
    for k in order:
        groups.setdefault(tuple(STRATA[key](candidates[k]) for key in keys), []).append(
            candidates[k]
        )
    draw = TrainingDraw(keys, groups)
    order_of_turns = group_turns(list(groups), asset.get("group_weights"))
    for i in range(n):  # turn i mod T, that group's next member, cycling
        label = order_of_turns[i % len(order_of_turns)]
        draw.labels.append(label)
        draw.configurations.append(draw.take(label))
    return draw


def built_models(cfg, configurations: list[Configuration]) -> list[Path]:
    """The MJCFs of `configurations` for the collision source of `cfg.collision` (built if
    missing)."""
    source = str(cfg.collision.source)
    library = repo_path(cfg.paths.library)
    build_library(  # a no-op for configurations that are already current
        list({c.id: c for c in configurations}.values()),
        WorkflowSettings.from_config(cfg),
        SOURCES,
        repo_path(cfg.paths.cache),
        library,
    )
    return [model_path(library, c.id, source) for c in configurations]


def training_configurations(cfg, n: int, seed: int = 0) -> list[Path]:
    """MJCFs of `n` configurations drawn from the `asset` group (built if missing).

    Configurations are drawn without replacement (cycling when n exceeds the category) in a
    seeded order, for the collision source of `cfg.collision`, from the parts of `asset.split`
    (train, test or all; all for a config written before the split existed). With
    `asset.stratify` (e.g. [category, kind]) the draw takes its groups in turn, so each
    category × kind gets about n / groups configurations however few the catalog has (one
    flap base among thirteen); with one group it is the plain draw. `asset.group_weights`
    gives some groups more turns (`group_turns`). Every consumer (training pool, evaluation,
    table, video) draws through here.
    """
    return built_models(cfg, training_draw(cfg, n, seed).configurations)
