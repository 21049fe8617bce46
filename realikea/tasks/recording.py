"""The opening task that keeps every control step of its episodes, for datasets of rollouts.

`RecordingTask` is an `OpenTask` (the env pool steps it like any task: `EnvPool(...,
task_factory=RecordingTask)`) whose episode record carries the episode step by step under
`steps` (an `EpisodeSteps`), with the configuration id, the env's seed and whether the policy
saw the door mirrored. The steps are the scene's: a door the policy sees and drives as its
hinge twin (`task.mirror_doors`, `realikea/tasks/mirror.py`) has its observations and actions
reflected back into the world's frame, so a dataset holds one frame for every door. Only an
episode the task itself ends carries them: one the pool cuts short (divergence, a bad action, a
lost worker) has no record of the task's.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from omegaconf import DictConfig

from realikea.errors import RealIkeaError
from realikea.tasks import mirror
from realikea.tasks.contacts import SAMPLE_FORCES
from realikea.tasks.contract import StepResult
from realikea.tasks.open_task import OpenTask


@dataclass(frozen=True)
class EpisodeSteps:
    """One episode's control steps: the observation before each action, the action, and what
    followed it."""

    observations: np.ndarray  # (T, observations.SIZE) in the world's frame
    # (T, ACTION_SIZE) the policy's, unclipped (the task clips to [-1, 1]), in the world's frame
    actions: np.ndarray
    rewards: np.ndarray  # (T,)
    openings: np.ndarray  # (T,) the front's joint after the step: m (drawer) or rad (hinge)
    contact_forces: np.ndarray  # (T, len(SAMPLE_FORCES)) N: the step's mean of each sample's

    @property
    def length(self) -> int:
        """Control steps (frames) of the episode."""
        return len(self.actions)


class RecordingTask(OpenTask):
    """An `OpenTask` whose episode records carry `steps`, `config_id`, `env_seed` and
    `mirrored`."""

    episode_keys = (*OpenTask.episode_keys, "steps", "config_id", "env_seed", "mirrored")

    def __init__(self, cfg: DictConfig, config_mjcf: Path, seed: int = 0):
        """The task of `OpenTask`; it needs the contact monitor (eval's `contacts.log`)."""
        super().__init__(cfg, config_mjcf, seed)
        if self.contact_monitor is None:
            raise RealIkeaError(
                "recording episodes needs the contact monitor for the per-step contact forces: "
                "set contacts.log=true"
            )
        self.seed = int(seed)
        self._rows: list[tuple] = []
        self._obs = self._action = None

    def reset(self) -> np.ndarray:
        """Start an episode and its recording."""
        obs = super().reset()
        self._obs, self._rows = self.reflected(obs, mirror.OBSERVATION_SIGNS), []
        return obs

    def apply_action(self, action) -> bool:
        """Keep the action, then act as the task does."""
        self._action = self.reflected(np.array(action, dtype=np.float64), mirror.ACTION_SIGNS)
        return super().apply_action(action)

    def evaluate(self, ik_ok: bool) -> StepResult:
        """The task's step result; the step is kept, and the episode handed over at its end."""
        result = super().evaluate(ik_ok)
        info = result.info
        row = (self._obs, self._action, result.reward, info["opening"], info["contact_forces"])
        self._rows.append(row)
        self._obs = self.reflected(result.obs, mirror.OBSERVATION_SIGNS)
        if result.terminated or result.truncated:
            info.update(steps=self._episode_steps(), config_id=self.config_id, env_seed=self.seed,
                        mirrored=self.mirrored)  # fmt: skip
        return result

    def _episode_steps(self) -> EpisodeSteps:
        """The kept steps of the episode as arrays."""
        obs, actions, rewards, openings, forces = zip(*self._rows, strict=True)
        return EpisodeSteps(
            np.array(obs, dtype=np.float64),
            np.array(actions, dtype=np.float64),
            np.array(rewards, dtype=np.float64),
            np.array(openings, dtype=np.float64),
            np.array(forces, dtype=np.float64).reshape(-1, len(SAMPLE_FORCES)),
        )
