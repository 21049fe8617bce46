"""PPO for one policy over several task groups (category x kind): advantages normalised within
each group's envs instead of over the whole batch (`agent.group_advantages`).

Why: rsl-rl normalises the advantages of the whole batch at once, so in a multi-task batch the
groups whose returns vary most set the scale, and a group not yet learned (small, flat returns)
gets advantages near zero and little gradient. Normalised per group, every group's advantages have
unit scale, as in a run of that group alone. Multi-task PPO of this kind: e.g. Hessel et al.
(2019), "Multi-task deep reinforcement learning with PopArt", which normalises per task.
"""

from __future__ import annotations

from collections.abc import Callable

import torch
from rsl_rl.algorithms import PPO
from tensordict import TensorDict

EPS = 1e-8  # rsl-rl's own in its whole-batch normalisation


def normalized_by_group(advantages: torch.Tensor, groups: torch.Tensor) -> torch.Tensor:
    """`advantages` (steps, envs, 1) with each group's envs (`groups`: an index per env) shifted
    to mean 0 and scaled to std 1 over that group's steps and envs."""
    out = torch.empty_like(advantages)
    for group in torch.unique(groups):
        chosen = advantages[:, groups == group]
        out[:, groups == group] = (chosen - chosen.mean()) / (chosen.std() + EPS)
    return out


class GroupPPO(PPO):
    """rsl-rl's PPO whose advantages are normalised per task group (see the module doc); the
    env tells each env's group (`RslRlVecEnv.group_index`)."""

    group_index: Callable[[], torch.Tensor]

    @staticmethod
    def construct_algorithm(obs: TensorDict, env, cfg: dict, device: str) -> GroupPPO:
        alg = PPO.construct_algorithm(obs, env, cfg, device)  # builds the class cfg names
        alg.group_index = env.group_index
        return alg

    def compute_returns(self, obs: TensorDict) -> None:
        per_mini_batch = self.normalize_advantage_per_mini_batch
        self.normalize_advantage_per_mini_batch = True  # returns only: no whole-batch scaling
        try:
            super().compute_returns(obs)
        finally:
            self.normalize_advantage_per_mini_batch = per_mini_batch
        if not per_mini_batch:
            groups = self.group_index().to(self.storage.advantages.device)
            self.storage.advantages = normalized_by_group(self.storage.advantages, groups)
