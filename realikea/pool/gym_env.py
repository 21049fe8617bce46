"""One opening task as a gymnasium env (for single-env tools and gymnasium's vector envs).

Observations are float32 (the privileged observation, realikea.tasks.observations), actions the
5-D command in [-1, 1]. `reset(seed=...)` reseeds the task's randomization. `render()` returns an
RGB frame from the scene's overview camera when built with render_mode="rgb_array" (offscreen on
the CPU). A non-finite action raises RealIkeaError: a single env has no pool to count it.
"""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import numpy as np
from omegaconf import DictConfig, OmegaConf

from realikea.tasks import observations
from realikea.tasks.open_task import ACTION_SIZE, OpenTask


class OpenTaskEnv(gym.Env):
    """The robot opening one configuration's front."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(
        self,
        cfg: DictConfig | dict,
        config_mjcf: Path | str,
        seed: int = 0,
        render_mode: str | None = None,
        width: int = 640,
        height: int = 480,
        camera: str = "overview",
    ):
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"render_mode={render_mode!r}: use None or 'rgb_array'")
        cfg = cfg if isinstance(cfg, DictConfig) else OmegaConf.create(cfg)
        self.task = OpenTask(cfg, Path(config_mjcf), seed)
        self.render_mode, self.camera = render_mode, camera
        self.width, self.height = width, height
        self._renderer = None
        self.metadata = {**self.metadata, "render_fps": round(1.0 / self._control_period())}
        self.observation_space = gym.spaces.Box(
            -np.inf, np.inf, (observations.SIZE,), dtype=np.float32
        )
        self.action_space = gym.spaces.Box(-1.0, 1.0, (ACTION_SIZE,), dtype=np.float32)

    def _control_period(self) -> float:
        return self.task.decimation * self.task.model.opt.timestep

    def set_iteration(self, iteration: int) -> None:
        """The training iteration, for the two-phase randomization (applies from the next reset)."""
        self.task.iteration = int(iteration)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        if seed is not None:
            self.task.rng = np.random.default_rng(seed)
        obs = self.task.reset()
        return obs.astype(np.float32), {}

    def step(self, action):
        result = self.task.step(np.asarray(action, dtype=np.float64))
        return (
            result.obs.astype(np.float32),
            float(result.reward),
            bool(result.terminated),
            bool(result.truncated),
            result.info,
        )

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        import mujoco

        if self._renderer is None:
            self._renderer = mujoco.Renderer(self.task.model, self.height, self.width)
        self._renderer.update_scene(self.task.data, camera=self.camera)
        return self._renderer.render()

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
