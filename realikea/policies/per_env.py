"""Base of the policies that keep per-env state and act one env at a time."""

from __future__ import annotations

import numpy as np

from realikea.tasks.open_task import ACTION_SIZE


class PerEnvPolicy:
    """`act` over a batch calls `_act_one(env, obs_row)` for each env in order."""

    def act(self, obs: np.ndarray) -> np.ndarray:
        actions = np.zeros((len(obs), ACTION_SIZE))
        for i, row in enumerate(obs):
            actions[i] = self._act_one(i, row)
        return actions

    def _act_one(self, i: int, obs: np.ndarray) -> np.ndarray:
        raise NotImplementedError
