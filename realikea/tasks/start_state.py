"""The start-state curriculum: a share of episodes start with the hand at the pre-grasp pose
(the TCP at the first approach target, handle + `task.targets.o1`, at the nominal pitch, gripper
open) instead of at home, optionally only in some category x kind groups.

    python train.py +task.pregrasp_share=0.3 +task.pregrasp_groups=[finger_pull_door]

Why: a group whose approach is hard to find (a finger-pull lip on a door) rarely reaches the
stage where pulling is rewarded, so PPO sees few of its successes; starting some episodes past
the approach gives it the later stages to learn from (a reverse curriculum in the sense of
Florensa et al. 2017, "Reverse curriculum generation for reinforcement learning"). Absent, both
keys mean off: every episode starts at home and no random number is drawn.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from omegaconf import DictConfig

from realikea.assets.catalog import GROUPS
from realikea.errors import RealIkeaError

# the curriculum's keys in `task`: a training device, which an evaluation of the run's
# checkpoint must not inherit with the rest of its task (realikea/eval/setup.py)
CURRICULUM_KEYS = ("pregrasp_share", "pregrasp_groups")


@dataclass(frozen=True)
class PregraspStart:
    """Which episodes start at the pre-grasp pose: a `share` of those of `groups` (all: empty)."""

    share: float = 0.0
    groups: tuple[str, ...] = ()

    @classmethod
    def from_config(cls, task: DictConfig) -> PregraspStart:
        """From `task.pregrasp_share` and `task.pregrasp_groups`; a share outside [0, 1] or an
        unknown group is refused, naming it."""
        share = task.get("pregrasp_share") or 0.0
        if isinstance(share, bool) or not isinstance(share, (int, float)) or not 0 <= share <= 1:
            raise RealIkeaError(f"task.pregrasp_share={share!r}: use a share in [0, 1]")
        groups = tuple(str(g) for g in (task.get("pregrasp_groups") or ()))
        unknown = [g for g in groups if g not in GROUPS]
        if unknown:
            raise RealIkeaError(
                f"task.pregrasp_groups: unknown group {', '.join(unknown)}; use {', '.join(GROUPS)}"
            )
        return cls(float(share), groups)

    def draws(self, group: str, rng: np.random.Generator) -> bool:
        """Whether this episode of `group` starts at the pre-grasp pose (a draw from `rng` only
        where the curriculum applies)."""
        if not self.share or (self.groups and group not in self.groups):
            return False
        return bool(rng.random() < self.share)
