"""Start-state curricula, training devices that start a share of some groups' episodes off the
task as evaluated:

- at the pre-grasp pose: the TCP at the first approach target, handle + `task.targets.o1`, at
  the nominal pitch, gripper open, the front closed;

      python train.py +task.pregrasp_share=0.3 +task.pregrasp_groups=[finger_pull_door]

- with the front ajar: opened to a uniform draw in `task.ajar_range` (fractions of the success
  mark), the hand at home, as if a hook had pulled it that far and come off (the episode counts
  as grasped, so the reward pays the opening from the first step, as it does after a slip).

      python train.py +task.ajar_share=0.3 +task.ajar_groups=[finger_pull_door]

Why: a group whose approach is hard to find (a finger-pull lip on a door) rarely reaches the
stage where pulling is rewarded, so PPO sees few of its successes; starting some episodes past
the approach gives it the later stages to learn from (a reverse curriculum in the sense of
Florensa et al. 2017, "Reverse curriculum generation for reinforcement learning"). The ajar
start gives it the state its finger-pull door partials end in: a hook that slipped short of the
mark, the door to be caught again and pulled on (`experiments/generalist/README.md`, round 6).
An episode draws the pre-grasp start first, the ajar start only if it did not take that one.
Absent, the keys mean off: every episode starts at home and no random number is drawn.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from omegaconf import DictConfig, ListConfig

from realikea.assets.catalog import GROUPS
from realikea.errors import RealIkeaError

# the curricula's keys in `task`: training devices, which an evaluation of the run's checkpoint
# must not inherit with the rest of its task (realikea/eval/setup.py)
CURRICULUM_KEYS = ("pregrasp_share", "pregrasp_groups", "ajar_share", "ajar_groups", "ajar_range")
# the final info's flag of an episode each curriculum began (OpenTask.episode_keys)
STARTS = ("pregrasp", "ajar")


def began_off_home(episode: dict) -> bool:
    """Whether a curriculum began this episode elsewhere than the task as evaluated starts."""
    return any(episode.get(flag) for flag in STARTS)


def share_and_groups(task: DictConfig, prefix: str) -> tuple[float, tuple[str, ...]]:
    """`task.<prefix>_share` and `task.<prefix>_groups`; a share outside [0, 1] or an unknown
    group is refused, naming it."""
    share = task.get(f"{prefix}_share") or 0.0
    if isinstance(share, bool) or not isinstance(share, (int, float)) or not 0 <= share <= 1:
        raise RealIkeaError(f"task.{prefix}_share={share!r}: use a share in [0, 1]")
    groups = tuple(str(g) for g in (task.get(f"{prefix}_groups") or ()))
    unknown = [g for g in groups if g not in GROUPS]
    if unknown:
        raise RealIkeaError(
            f"task.{prefix}_groups: unknown group {', '.join(unknown)}; use {', '.join(GROUPS)}"
        )
    return float(share), groups


@dataclass(frozen=True)
class ShareOfGroups:
    """A curriculum's episodes: a `share` of those of `groups` (all: empty)."""

    share: float = 0.0
    groups: tuple[str, ...] = ()

    def draws(self, group: str, rng: np.random.Generator) -> bool:
        """Whether this episode of `group` takes the curriculum's start (a draw from `rng` only
        where the curriculum applies)."""
        if not self.share or (self.groups and group not in self.groups):
            return False
        return bool(rng.random() < self.share)


@dataclass(frozen=True)
class PregraspStart(ShareOfGroups):
    """Which episodes start at the pre-grasp pose."""

    @classmethod
    def from_config(cls, task: DictConfig) -> PregraspStart:
        """From `task.pregrasp_share` and `task.pregrasp_groups` (`share_and_groups`)."""
        return cls(*share_and_groups(task, "pregrasp"))


@dataclass(frozen=True)
class AjarStart(ShareOfGroups):
    """Which episodes start with the front ajar, and how far: opened to a uniform fraction in
    [low, high) of the success mark."""

    low: float = 0.4
    high: float = 1.0

    @classmethod
    def from_config(cls, task: DictConfig) -> AjarStart:
        """From `task.ajar_share`, `task.ajar_groups` (`share_and_groups`) and `task.ajar_range`
        ([low, high], 0 <= low <= high <= 1; absent: [0.4, 1.0]), refused by name if bad."""
        share, groups = share_and_groups(task, "ajar")
        bounds = task.get("ajar_range")
        if bounds is None:
            return cls(share, groups)
        values = list(bounds) if isinstance(bounds, (list, tuple, ListConfig)) else []
        numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)
        if len(values) != 2 or not numbers or not 0 <= values[0] <= values[1] <= 1:
            raise RealIkeaError(
                f"task.ajar_range={bounds!r}: use [low, high], fractions of the success mark "
                "with 0 <= low <= high <= 1"
            )
        return cls(share, groups, float(values[0]), float(values[1]))

    def opening(self, group: str, rng: np.random.Generator) -> float | None:
        """The fraction of the success mark this episode of `group` starts opened to, or None
        for a closed front (random numbers drawn from `rng` only where the curriculum
        applies)."""
        return float(rng.uniform(self.low, self.high)) if self.draws(group, rng) else None
