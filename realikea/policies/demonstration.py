"""Demonstrations: one OpenTask's episodes recorded action by action, saved as one `.npz`.

A demonstration file holds, per episode k, `actions_k` (T, 5), `observations_k` (T + 1, 28: the
observation before every action and the last one) and `rewards_k` (T,), plus `metadata`: one
JSON string with the observation layout and action size (a replay refuses another task layout),
the configuration id, its MJCF path and SHA-256, the seed, the command-line overrides and the
resolved config they composed, and one summary per episode (steps, outcome, termination,
strategy, complete). Files are written atomically (a temporary file beside the target, then
`os.replace`), so a crash never leaves half a demonstration.

`Session` steps one task exactly the way the env pool steps env 0 of a one-env pool under
`realikea eval` (reset at construction, reset again by the eval loop, auto-reset after every
episode), so a recording replays bit for bit through the pool (`policy=replay`).
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from omegaconf import DictConfig, OmegaConf

from realikea.errors import RealIkeaError
from realikea.tasks import observations
from realikea.tasks.contract import StepResult
from realikea.tasks.open_task import ACTION_SIZE, OpenTask

FORMAT = "realikea-demonstration"
VERSION = 1
# what an episode summary keeps of the task's final info
_SUMMARY_KEYS = ("outcome", "termination", "opening", "strategy")


@dataclass
class Episode:
    """One recorded episode; `complete` is False when the operator cut it short."""

    actions: np.ndarray  # (T, ACTION_SIZE)
    observations: np.ndarray  # (T + 1, the size of the layout it was recorded with)
    rewards: np.ndarray  # (T,)
    summary: dict = field(default_factory=dict)

    @property
    def steps(self) -> int:
        return len(self.actions)


@dataclass
class Demonstration:
    """Episodes on one configuration and seed, and what is needed to replay them."""

    episodes: list[Episode]
    metadata: dict

    @property
    def config_id(self) -> str:
        return self.metadata["config_id"]

    @property
    def seed(self) -> int:
        return int(self.metadata["seed"])

    @property
    def config(self) -> DictConfig:
        """The resolved config of the recording."""
        return OmegaConf.create(self.metadata["config"])


def file_sha256(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


class Recorder:
    """Collects the steps of one task's episodes; `save` writes them atomically."""

    def __init__(
        self,
        task: OpenTask,
        cfg: DictConfig,
        mjcf: Path,
        seed: int,
        overrides: list[str] | tuple[str, ...] = (),
        source: str = "teleop",
    ):
        self.metadata = {
            "format": FORMAT,
            "version": VERSION,
            "source": source,
            "observation_layout": [list(item) for item in observations.LAYOUT],
            "action_size": ACTION_SIZE,
            "control_period": task.decimation * task.model.opt.timestep,
            "config_id": task.config_id,
            "part": task.part.id,
            "base": task.base.id,
            "category": task.part.category,
            "mjcf": str(mjcf),
            "mjcf_sha256": file_sha256(mjcf),
            "seed": int(seed),
            "overrides": list(overrides),
            "config": OmegaConf.to_container(cfg, resolve=True),
        }
        self.finished: list[Episode] = []
        self._actions: list[np.ndarray] = []
        self._obs: list[np.ndarray] = []
        self._rewards: list[float] = []

    def begin(self, obs: np.ndarray) -> None:
        self._actions, self._obs, self._rewards = [], [np.array(obs, dtype=np.float64)], []

    def add(self, action: np.ndarray, result: StepResult) -> None:
        self._actions.append(np.array(action, dtype=np.float64))
        self._obs.append(np.array(result.obs, dtype=np.float64))
        self._rewards.append(float(result.reward))

    @property
    def current_steps(self) -> int:
        return len(self._actions)

    def end(self, info: dict, complete: bool = True) -> Episode:
        summary = {k: info[k] for k in _SUMMARY_KEYS if k in info}
        summary.update(steps=len(self._actions), complete=bool(complete))
        summary["episode_return"] = float(sum(self._rewards))  # the task's own sum, in order
        episode = Episode(
            np.array(self._actions, dtype=np.float64).reshape(-1, ACTION_SIZE),
            np.array(self._obs, dtype=np.float64).reshape(-1, observations.SIZE),
            np.array(self._rewards, dtype=np.float64),
            summary,
        )
        self.finished.append(episode)
        self._actions, self._obs, self._rewards = [], [], []
        return episode

    def demonstration(self) -> Demonstration:
        meta = dict(self.metadata, episodes=[e.summary for e in self.finished])
        meta["recorded_at"] = time.strftime("%Y-%m-%dT%H:%M:%S%z")
        return Demonstration(list(self.finished), meta)

    def save(self, path: Path) -> Path:
        return save_demonstration(self.demonstration(), path)


def save_demonstration(demo: Demonstration, path: Path) -> Path:
    """Write a demonstration atomically (temporary file in the same directory, then rename)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    arrays = {"metadata": np.array(json.dumps(demo.metadata))}
    for k, e in enumerate(demo.episodes):
        arrays[f"actions_{k:03d}"] = e.actions
        arrays[f"observations_{k:03d}"] = e.observations
        arrays[f"rewards_{k:03d}"] = e.rewards
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez_compressed(f, **arrays)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def load_demonstration(path: Path) -> Demonstration:
    """Read and check a demonstration; any problem is a RealIkeaError naming the file."""
    path = Path(path)
    if not path.is_file():
        raise RealIkeaError(f"demonstration not found: {path}")
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
        meta = json.loads(str(arrays["metadata"]))
    except Exception as err:  # not a zip, truncated, no metadata, bad JSON
        raise RealIkeaError(f"{path}: not a readable demonstration file ({err})") from err
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise RealIkeaError(f"{path}: not a Real-IKEA demonstration (no {FORMAT!r} metadata)")
    if meta.get("version") != VERSION:
        raise RealIkeaError(f"{path}: demonstration format {meta.get('version')}, need {VERSION}")
    layout = [(str(name), int(size)) for name, size in meta.get("observation_layout") or []]
    try:  # an older layout (the appendix's terms only) replays: its actions are the demonstration
        observations.selector(layout)
    except KeyError as err:
        raise RealIkeaError(
            f"{path}: recorded with observation layout {layout}, which this code cannot give "
            f"({err.args[0]})"
        ) from err
    obs_size = sum(size for _, size in layout)
    if meta.get("action_size") != ACTION_SIZE:
        raise RealIkeaError(
            f"{path}: recorded with {meta.get('action_size')}-D actions, this task takes "
            f"{ACTION_SIZE}"
        )
    missing = [k for k in ("config_id", "seed", "config", "episodes") if k not in meta]
    if missing:
        raise RealIkeaError(f"{path}: demonstration metadata lacks {', '.join(missing)}")
    episodes = []
    for k, summary in enumerate(meta["episodes"]):
        try:
            actions = arrays[f"actions_{k:03d}"]
            obs = arrays[f"observations_{k:03d}"]
            rewards = arrays[f"rewards_{k:03d}"]
        except KeyError as err:
            raise RealIkeaError(f"{path}: episode {k} is missing ({err})") from err
        steps = len(actions)
        if (
            actions.shape != (steps, ACTION_SIZE)
            or obs.shape != (steps + 1, obs_size)
            or rewards.shape != (steps,)
        ):
            raise RealIkeaError(
                f"{path}: episode {k} has actions {actions.shape}, observations {obs.shape}; "
                f"this task takes {ACTION_SIZE}-D actions and {obs_size}-D observations "
                "(its recorded layout)"
            )
        if not np.all(np.isfinite(actions)):
            raise RealIkeaError(f"{path}: episode {k} holds non-finite actions")
        episodes.append(Episode(actions.astype(np.float64), obs, rewards, dict(summary)))
    if not episodes:
        raise RealIkeaError(f"{path}: the demonstration holds no episode")
    return Demonstration(episodes, meta)


class Session:
    """One task stepped episode after episode as env 0 of a one-env pool in `realikea eval`.

    The pool resets a task when it is built and `run_episodes` resets it again; afterwards every
    ended episode is followed by one reset. Keeping that order keeps the task's random stream
    (pose randomization) in step with a replay through the pool.
    """

    def __init__(self, task: OpenTask, recorder: Recorder | None = None):
        self.task, self.recorder = task, recorder
        task.reset()  # the pool's reset at construction
        self.obs = task.reset()  # run_episodes' reset
        if recorder is not None:
            recorder.begin(self.obs)

    def step(self, action) -> tuple[StepResult, Episode | None]:
        """One control step; returns its result and the recorded episode if this one ended."""
        action = np.asarray(action, dtype=np.float64)
        result = self.task.step(action)
        if self.recorder is not None:
            self.recorder.add(action, result)
        if not (result.terminated or result.truncated):
            self.obs = result.obs
            return result, None
        episode = self.recorder.end(result.info) if self.recorder is not None else None
        self._restart()
        return result, episode

    def cut(self, termination: str = "operator_reset") -> Episode | None:
        """End the current episode early (recorded as incomplete) and start the next one.

        Nothing happens before the episode's first step (a reset would advance the task's
        random stream past what a replay through the pool does).
        """
        task = self.task
        if task.state.steps == 0:
            return None
        episode = None
        if self.recorder is not None:
            info = {"termination": termination, "opening": task.opening}
            episode = self.recorder.end(info, complete=False)
        self._restart()
        return episode

    def finish(self) -> Episode | None:
        """Close the session: keep a started episode as incomplete."""
        if self.recorder is not None and self.recorder.current_steps:
            info = {"termination": "operator_quit", "opening": self.task.opening}
            return self.recorder.end(info, complete=False)
        return None

    def _restart(self) -> None:
        self.obs = self.task.reset()
        if self.recorder is not None:
            self.recorder.begin(self.obs)
