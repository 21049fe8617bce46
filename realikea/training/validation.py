"""A teacher judged on the validation draw: the success of its mean action on each of its groups.

A teacher's training success (its last full window, `realikea.training.metrics`) is that of its
policy with its exploration noise; evaluation runs the policy's mean action. On the aims' seed
200 the door teacher opened two-point doors 0.95 in training, and on the validation draw 0.83 of 100
episodes on its mean action (most failures stalled, pushing near the bar) and 1.00 on its samples
(`policy.sample`; experiments/generalist/README.md, round 20), so a rule read on training success
let it teach a group its student then missed. A
pipeline with `pipeline.judge: validation` reads these rates instead: train parts, the sweep's
validation seed (never the test draw), randomized poses, and the launch's own collision source,
resistance mode, scene, parts and bases (`CARRIED`); with `pipeline.judge_resistances` also in
those modes (the aims judge a default generalist in smooth and high, its teachers train in normal);
with `pipeline.judge_small_parts` also on the small-part reads of those categories' groups
(`small_part_overrides`).
"""

from __future__ import annotations

from pathlib import Path

from realikea.assets.catalog import Catalog, kind_and_category
from realikea.assets.split import IMPORTED, main_dimension
from realikea.config import override_key
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.sweep import VALIDATION_SEED
from realikea.files import shown_path

# the launch overrides a teacher's validation keeps (keys and their subkeys): what it trains on
# besides the group (collision source, resistance, scene, its parts and bases), where the library
# is, and how its envs step
CARRIED = (
    "collision",
    "resistance",
    "scene",
    "paths",
    "asset.part",
    "asset.base",
    "env.num_workers",
)


# the small-part reads of a group (`small_part_overrides`): their names and the hinge side each
# holds the draw to (None: every base of the kind). A door is read on each side apart: the aims'
# two-point door misses fell on the left-hinged doors (experiments/generalist/README.md, round 26)
SMALL_PART_SIDES = {"small": None, "small_left": "left", "small_right": "right"}


def small_part_reads(group: str) -> list[str]:
    """The names of a group's small-part reads: one on each hinge side for a door, else one."""
    kind, _ = kind_and_category(group)
    return ["small_left", "small_right"] if kind == "door" else ["small"]


def smallest_of_families(parts: list) -> set[str]:
    """The id of each family's smallest part among `parts` (by its main dimension,
    `realikea.assets.split.main_dimension`)."""
    smallest: dict[str, tuple[float, str]] = {}
    for part in parts:
        size = (main_dimension(part), part.id)
        smallest[part.family] = min(smallest.get(part.family, size), size)
    return {part_id for _, part_id in smallest.values()}


def small_part_overrides(group: str, read: str) -> list[str]:
    """The overrides holding a group's validation draw to its small-part read `read`: each
    family's smallest train part (the category's other train parts withheld), on the read's
    hinge side. The held-out split keeps back parts smaller than every train part of their
    family (realikea/catalog/split.csv); these are the nearest the train parts come to them."""
    _, category = kind_and_category(group)
    catalog = Catalog.load()
    train = [p for p in catalog.parts_of_split(catalog.parts_in(category), "train")
             if p.family != IMPORTED]  # fmt: skip
    keep = smallest_of_families(train)
    others = sorted(p.id for p in train if p.id not in keep)
    side = SMALL_PART_SIDES[read]
    return [f"asset.withhold=[{','.join(others)}]", *([f"asset.hinge={side}"] * bool(side))]


def carried(key: str, prefix: str) -> bool:
    """Whether the override key `key` is `prefix` or one of its subkeys."""
    return key == prefix or key.startswith(prefix + ".")


def validation_overrides(
    checkpoint: Path,
    group: str,
    episodes: int,
    launch: list[str],
    resistance: str = "",
    small_parts: str = "",
):
    """`realikea eval` overrides judging `checkpoint` on `group` on the validation draw, in
    the launch's resistance mode or the one named, or on its small-part read `small_parts`."""
    kind, category = kind_and_category(group)
    carry = [key for key in CARRIED if not (resistance and key == "resistance")]
    cell = [o for o in launch if any(carried(override_key(o), key) for key in carry)]
    mode = [f"resistance={resistance}"] if resistance else []
    return [
        "policy=checkpoint", f"policy.path={shown_path(Path(checkpoint).resolve())}",
        f"asset={category}", f"asset.kind={kind}", "asset.split=train", "dr=randomized",
        f"episodes={episodes}", f"env.seed={VALIDATION_SEED}", *cell, *mode,
        *(small_part_overrides(group, small_parts) if small_parts else []),
    ]  # fmt: skip


def validation_success(
    checkpoint: Path,
    groups: list[str],
    episodes: int,
    launch: list[str],
    label: str,
    resistance: str = "",
    small_parts: str = "",
) -> dict[str, float]:
    """Each group's success of `checkpoint`'s mean action over `episodes` validation episodes,
    in the launch's resistance mode or the one named, or on its small-part read `small_parts`
    (`SMALL_PART_SIDES`)."""
    rates = {}
    for group in groups:
        overrides = validation_overrides(
            checkpoint, group, episodes, launch, resistance, small_parts
        )
        cfg, policy = eval_setup(overrides)
        rates[group] = float(evaluate(cfg, policy, progress=False).summary()["success"])
        where = f" in {resistance}" if resistance else ""
        side = SMALL_PART_SIDES.get(small_parts)
        where += ", each family's smallest part" if small_parts else ""
        where += f" on {side}-hinged doors" if side else ""
        print(f"{label} on the validation draw{where}: {group} {rates[group]:.2f} "
              f"({episodes} episodes)", flush=True)  # fmt: skip
    return rates
