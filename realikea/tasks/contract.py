"""The task contract, as a Protocol: what the env pool (`realikea.pool`) and a rollout call.

`OpenTask` (`realikea/tasks/open_task.py`) is the opening task; a new task is any class with these
members, handed to the pool as `EnvPool(..., task_factory=MyTask)`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np
from omegaconf import DictConfig


@dataclass(frozen=True)
class StepResult:
    """One control step's outcome; `info["diverged"]` flags a blown-up state (the pool resets)."""

    obs: np.ndarray
    reward: float
    terminated: bool
    truncated: bool
    info: dict


@runtime_checkable
class Task(Protocol):
    """One env: episodes on one configuration, stepped in three calls so the pool can count a
    failing action, a diverging simulation and a finished episode apart."""

    observation_size: ClassVar[int]
    action_size: ClassVar[int]
    episode_keys: ClassVar[tuple[str, ...]]  # what the pool keeps of a finished episode's info
    horizon: int  # control steps before an episode is truncated
    iteration: int  # the training iteration (schedules read it; the pool sets it)

    def reset(self) -> np.ndarray:
        """Start an episode; its first observation."""
        ...

    def apply_action(self, action: np.ndarray) -> bool:
        """Turn an action into actuator targets; False when it cannot be followed (IK failed)."""
        ...

    def simulate(self) -> None:
        """Advance the physics by one control period."""
        ...

    def evaluate(self, ok: bool) -> StepResult:
        """Observation, reward and end flags after `simulate` (`ok`: what apply_action said)."""
        ...

    def step(self, action: np.ndarray) -> StepResult:
        """apply_action, simulate and evaluate in one call (one episode at a time, no pool)."""
        ...

    def facts(self) -> Any:
        """The current episode's scene, as scripted policies read it at their reset."""
        ...


TaskFactory = Callable[[DictConfig, Path, int], Task]  # (cfg, configuration MJCF, seed) -> task
