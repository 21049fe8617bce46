"""The envs one worker owns (all of them in-process): steps whole control steps of its tasks and
writes their rows of the shared arrays; a task that diverges or gets a non-finite action ends its
episode and starts the next (counted)."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np

from realikea.pool.shared import COUNTERS
from realikea.tasks.contract import TaskFactory

_C = {name: k for k, name in enumerate(COUNTERS)}


class EnvSlice:
    """Tasks `task_factory(cfg, path, seed)` (`Task`s, realikea/tasks/contract.py) for the
    global env ids `env_ids`."""

    def __init__(
        self, task_factory: TaskFactory, cfg, paths, seeds, env_ids, arrays, worker, iteration
    ):
        self.factory, self.cfg = task_factory, cfg
        self.ids = [int(i) for i in env_ids]
        self.tasks = [task_factory(cfg, Path(p), int(s)) for p, s in zip(paths, seeds, strict=True)]
        self.pending: dict[int, tuple[str, int]] = {}  # env id -> (MJCF, seed) at its next episode
        self.a = arrays
        self.counters = arrays["counters"][worker]
        self.episode_keys = tuple(getattr(task_factory, "episode_keys", ()))
        self.set_iteration(iteration)
        self.reset()

    def horizons(self) -> list[int]:
        return [int(t.horizon) for t in self.tasks]

    def facts(self, env_ids) -> dict:
        """The current episode's facts of the given global env ids that this slice owns."""
        wanted = {int(i) for i in env_ids}
        return {i: t.facts() for t, i in zip(self.tasks, self.ids, strict=True) if i in wanted}

    def set_iteration(self, iteration: int) -> None:
        self.iteration = int(iteration)
        for task in self.tasks:
            task.iteration = self.iteration

    def reassign(self, moves: dict[int, tuple[str, int]]) -> None:
        """Move envs to other configurations ({env id: (MJCF, seed)}) from their next episode."""
        self.pending.update({int(i): m for i, m in moves.items() if int(i) in self.ids})

    def _start(self, task, i) -> None:
        """Start env i's next episode, on its new configuration if one is pending."""
        if i in self.pending:
            path, seed = self.pending.pop(i)
            task = self.factory(self.cfg, Path(path), int(seed))
            task.iteration = self.iteration
            self.tasks[self.ids.index(i)] = task
        self.a["obs"][i] = task.reset()

    def reset(self, env_ids=None) -> None:
        """Start new episodes for the given global env ids (all of this slice's by default)."""
        wanted = None if env_ids is None else {int(i) for i in env_ids}
        for task, i in zip(list(self.tasks), self.ids, strict=True):
            if wanted is None or i in wanted:
                self._start(task, i)

    def _end(self, task, i, final_obs, reward, terminated, truncated, record) -> dict:
        """Write the last step of an episode, keep its final observation, start the next one."""
        a = self.a
        a["final_obs"][i] = final_obs
        a["reward"][i], a["terminated"][i], a["truncated"][i] = reward, terminated, truncated
        self._start(task, i)
        record["env"] = i
        return record

    def step(self) -> list[dict]:
        """One control step of every env; returns the records of the episodes that ended."""
        a = self.a
        actions, obs, rewards = a["action"], a["obs"], a["reward"]
        finite_actions = np.isfinite(actions[self.ids]).all(axis=1).tolist()  # one check for all
        ended = []
        for task, i, finite_action in zip(list(self.tasks), self.ids, finite_actions, strict=True):
            if not finite_action:
                self.counters[_C["bad_action_resets"]] += 1
                record = {"termination": "bad_action"}
                ended.append(self._end(task, i, obs[i].copy(), 0.0, False, True, record))
                continue
            ok = task.apply_action(actions[i])
            try:
                task.simulate()
                result = task.evaluate(ok)
                fatal = False
            except mujoco.FatalError:
                result, fatal = None, True
            finite = not fatal and np.isfinite(result.obs).all() and math.isfinite(result.reward)
            if fatal or not finite or result.info["diverged"]:
                self.counters[_C["divergence_resets"]] += 1
                record = {"termination": "diverged"}
                ended.append(self._end(task, i, np.zeros(obs.shape[1]), 0.0, True, False, record))
                continue
            if result.terminated or result.truncated:
                info = result.info
                record = {k: info[k] for k in self.episode_keys if k in info}
                ended.append(
                    self._end(
                        task, i, result.obs, result.reward, result.terminated, result.truncated,
                        record,
                    )
                )  # fmt: skip
            else:
                obs[i] = result.obs
                rewards[i] = result.reward
                a["terminated"][i] = a["truncated"][i] = False
        return ended
