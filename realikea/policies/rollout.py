"""One episode of a policy on one task, step by step: the loop scripted studies and tests share."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from realikea.tasks.open_task import OpenTask, StepResult


def episode(
    task: OpenTask, policy, steer: Callable[[int, np.ndarray], np.ndarray] | None = None
) -> Iterator[StepResult]:
    """Reset `task` and `policy` (as env 0), then yield each step's result until the episode
    ends (terminated or truncated); `steer(t, action)` may change the policy's action at step t
    before it is taken."""
    obs = task.reset()
    policy.reset([0], [task.facts()])
    t = 0
    while True:
        action = policy.act(obs[None])[0]
        result = task.step(action if steer is None else steer(t, action))
        obs = result.obs
        yield result
        if result.terminated or result.truncated:  # the task truncates at its horizon
            return
        t += 1


def final_info(task: OpenTask, policy) -> dict:
    """The last step's info of one episode (outcome, strategy, termination, ...)."""
    *_, last = episode(task, policy)
    return last.info
