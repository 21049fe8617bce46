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
those modes (the aims judge a default generalist in smooth and high, its teachers train in normal).
"""

from __future__ import annotations

from pathlib import Path

from realikea.assets.catalog import kind_and_category
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


def carried(key: str, prefix: str) -> bool:
    """Whether the override key `key` is `prefix` or one of its subkeys."""
    return key == prefix or key.startswith(prefix + ".")


def validation_overrides(
    checkpoint: Path, group: str, episodes: int, launch: list[str], resistance: str = ""
):
    """`realikea eval` overrides judging `checkpoint` on `group` on the validation draw, in
    the launch's resistance mode or the one named."""
    kind, category = kind_and_category(group)
    carry = [key for key in CARRIED if not (resistance and key == "resistance")]
    cell = [o for o in launch if any(carried(override_key(o), key) for key in carry)]
    mode = [f"resistance={resistance}"] if resistance else []
    return [
        "policy=checkpoint", f"policy.path={shown_path(Path(checkpoint).resolve())}",
        f"asset={category}", f"asset.kind={kind}", "asset.split=train", "dr=randomized",
        f"episodes={episodes}", f"env.seed={VALIDATION_SEED}", *cell, *mode,
    ]  # fmt: skip


def validation_success(
    checkpoint: Path,
    groups: list[str],
    episodes: int,
    launch: list[str],
    label: str,
    resistance: str = "",
) -> dict[str, float]:
    """Each group's success of `checkpoint`'s mean action over `episodes` validation episodes,
    in the launch's resistance mode or the one named."""
    rates = {}
    for group in groups:
        overrides = validation_overrides(checkpoint, group, episodes, launch, resistance)
        cfg, policy = eval_setup(overrides)
        rates[group] = float(evaluate(cfg, policy, progress=False).summary()["success"])
        where = f" in {resistance}" if resistance else ""
        print(f"{label} on the validation draw{where}: {group} {rates[group]:.2f} "
              f"({episodes} episodes)", flush=True)  # fmt: skip
    return rates
