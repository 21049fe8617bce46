"""An intervention on a policy's grasp: every closing gripper command driven to fully closed, so
the gripper's drive squeezes with its full force whenever the policy asks to close at all."""

from __future__ import annotations

import numpy as np

GRIP = 4  # the action's gripper command (OpenTask.apply_action): -1 closed, +1 open


class FullSqueeze:
    """`policy` with its gripper command at -1 (fully closed) whenever it is below 0; keeps the
    policy's own closing commands, before the change, in `closing`."""

    def __init__(self, policy):
        self.policy = policy
        self.closing: list[float] = []

    def reset(self, env_ids, facts) -> None:
        self.policy.reset(env_ids, facts)

    def act(self, obs: np.ndarray) -> np.ndarray:
        action = self.policy.act(obs)
        closing = action[:, GRIP] < 0.0
        self.closing += np.clip(action[closing, GRIP], -1.0, 0.0).tolist()
        action[closing, GRIP] = -1.0
        return action
