"""The task's reward as named terms of one variant (`task/reward=<variant>`): the weighted sum of
the variant's terms in their order, times its `scale`; the task logs each term's episode sum.
A variant's params dataclass is the one schema of its constants: `store_configs` gives Hydra the
config group from its defaults. Pure Python on one env's numbers (no simulator), so the config
layer can register it.

Variants: `gated` (the default: stages read from the scene every step, grasp readiness from
contact) and `appendix` (the paper's stages latched, what every committed checkpoint before the
gated variant was trained on). A config without `variant` is the appendix's.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, fields
from typing import Any

from hydra.core.config_store import ConfigStore

from realikea.errors import RealIkeaError
from realikea.rewards import appendix, gated
from realikea.rewards.terms import StepValues

DEFAULT_VARIANT = "appendix"  # what a config naming no variant was trained on
STAGES = 4  # every variant's stages: approach, refine, close, open


@dataclass(frozen=True)
class Variant:
    """A reward variant: its constants, how the stage moves, and its named terms."""

    name: str
    params: type  # frozen dataclass of the constants
    next_stage: Callable[[int, StepValues, Any], int]
    # name -> (term, the params field that weighs it; None: the term carries its own weights)
    terms: Mapping[str, tuple[Callable[[StepValues, Any], float], str | None]]
    reads_grip: bool  # whether its stages read the straddle and the contacts (params give
    # straddle_radius, hook_cos and w_push); the task skips the contact scan otherwise

    def weighted_terms(self, v: StepValues, p) -> list[tuple[str, float]]:
        """(name, weighted and scaled value) of every term, in order."""
        scale = getattr(p, "scale", 1.0)
        out = []
        for name, (term, weight) in self.terms.items():
            value = term(v, p)
            if weight is not None:
                value = getattr(p, weight) * value
            out.append((name, value if scale == 1.0 else scale * value))
        return out


VARIANTS = {
    "appendix": Variant(
        "appendix", appendix.AppendixParams, appendix.next_stage, appendix.TERMS, False
    ),
    "gated": Variant("gated", gated.GatedParams, gated.next_stage, gated.TERMS, True),
}


def variant_name(reward_cfg: Mapping) -> str:
    """The variant a `task.reward` config names (none: `DEFAULT_VARIANT`), checked."""
    name = str(reward_cfg.get("variant") or DEFAULT_VARIANT)
    if name not in VARIANTS:
        raise RealIkeaError(
            f"task.reward.variant={name!r} is not a reward variant: use one of "
            f"{', '.join(VARIANTS)} (task/reward=<variant>)"
        )
    return name


def reward_from_config(reward_cfg: Mapping):
    """(variant, params) of a `task.reward` config; unknown keys name the variant's fields."""
    variant = VARIANTS[variant_name(reward_cfg)]
    values = {k: v for k, v in dict(reward_cfg).items() if k != "variant"}
    known = {f.name for f in fields(variant.params)}
    unknown = sorted(set(values) - known)
    if unknown:
        raise RealIkeaError(
            f"task.reward: {', '.join(unknown)} not a constant of the {variant.name!r} reward "
            f"variant (its constants: {', '.join(sorted(known))})"
        )
    return variant, variant.params(**values)


def store_configs() -> None:
    """Register `task/reward=<variant>` for every variant with Hydra: its name and its params'
    defaults (the YAML a Hydra config group would otherwise need, written once)."""
    store = ConfigStore.instance()
    for name, variant in VARIANTS.items():
        node = {"variant": name, **asdict(variant.params())}
        store.store(group="task/reward", name=name, node=node)
