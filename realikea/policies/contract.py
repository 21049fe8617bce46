"""The policy contract: what `realikea eval` runs against the env pool, as a Protocol.

Learned, scripted, sampled and teleoperated policies all have these three members; a new one is
named in `realikea/policies/registry.py: POLICIES` and given a `realikea/conf/policy/<name>.yaml`.
Optional members the evaluation looks for: `run_cfg` (the configuration a checkpoint was trained
with), `configure(cfg, overrides)` (a replay's recorded configuration), `run_interactive`
(teleoperation) and `note` ({env: what the policy did}, kept on the episodes that just ended).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol, runtime_checkable

import numpy as np
from omegaconf import DictConfig


@runtime_checkable
class Policy(Protocol):
    """Actions for every env of a pool at once; told which envs start a new episode."""

    @classmethod
    def from_config(cls, cfg: DictConfig) -> Policy:
        """The policy the composed eval config (`cfg.policy`) describes."""
        ...

    def reset(self, env_ids: Sequence[int], facts: Sequence[Any]) -> None:
        """New episodes begin in `env_ids`, with the scenes `facts` (`Task.facts()`, one each)."""
        ...

    def act(self, obs: np.ndarray) -> np.ndarray:
        """(num_envs, action_size) actions for the (num_envs, observation_size) observations."""
        ...
