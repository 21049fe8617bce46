"""N tasks stepped in parallel on all cores, with auto-reset, seeding and self-healing.

Design (measured in experiments/benchmarks/bench_pool.md): about a quarter of a control step is
the task's Python (mink IK, reward, observation), so threading only the physics substeps
(`mujoco.rollout` releases the GIL) would leave that serial; instead each worker process owns a
slice of the envs and runs whole control steps (`realikea/pool/processes.py`). Actions,
observations, rewards and flags live in one shared-memory block (`realikea/pool/shared.py`).

The pool is task-agnostic: env i is `task_factory(cfg, configurations[i], seed + i)` (a `Task`,
`realikea/tasks/contract.py`); `from_config` uses the opening task. It owns
the episode bookkeeping: steps and return of what the learner saw of every episode, however it
ended.

Backends, one interface (`InProcess` for `num_workers=0`, `Processes` otherwise): `horizons`,
`restarts`, `pids`; `step() -> (records of ended episodes, workers lost)`, `reset(env_ids)`,
`facts(env_ids)`, `set_iteration(it)`, `reassign({env: (MJCF, seed)})`, `close()`.

Robustness, all counted in `pool.counters`:
- a worker that dies (or exceeds `step_timeout`) is restarted; its envs start new episodes
  (`worker_restarts`); the lost episodes are reported with termination "worker_crash";
- physics divergence (the task's own check, a MuJoCo fatal error, or any non-finite observation
  or reward) ends that episode with zero reward and resets the env (`divergence_resets`);
- a non-finite action resets that env instead of being stepped (`bad_action_resets`).
A diverged episode ends `terminated` with zero reward; one cut short by the pool (worker crash,
bad action) ends `truncated`. Neither carries an `outcome` (they are counted instead).

With workers, a script that builds a pool needs the `if __name__ == "__main__":` guard (spawn
re-imports the main module).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from omegaconf import DictConfig, OmegaConf

from realikea.assets.library import training_configurations
from realikea.errors import RealIkeaError
from realikea.pool import shared
from realikea.pool.in_process import InProcess
from realikea.pool.processes import Processes, available_cores
from realikea.spawn import spawn_context
from realikea.tasks.open_task import OpenTask

# a reassigned env's k-th seed is seed + i + num_envs * (RESEED + k): apart from the worker
# restarts' seed + i + num_envs * generation
RESEED = 1_000_000


class EnvPool:
    """`len(configurations)` tasks (env i on configurations[i], seeded seed + i).

    `step(actions)` returns (obs, reward, terminated, truncated, info) as numpy arrays over the
    envs. An env whose episode ended is reset at once: `obs` holds its new episode's first
    observation, `info["final_obs"]` the last one of the finished episode, and
    `info["episodes"]` one dict per finished episode: env, termination, episode_steps,
    episode_return, and the task's own record (`task_factory.episode_keys`: for the opening task
    its outcome, opening, reward term sums and contact statistics) when the task itself ended it.
    """

    def __init__(
        self,
        cfg: DictConfig,
        configurations: Sequence[Path | str],
        seed: int | None = None,
        num_workers: int | None = None,
        step_timeout: float | None = None,
        task_factory: Callable = OpenTask,
    ):
        env_cfg = cfg.get("env") or {}
        self.cfg = cfg
        self.configurations = [Path(p) for p in configurations]
        self.num_envs = len(self.configurations)
        if self.num_envs == 0:
            raise RealIkeaError("the env pool needs at least one configuration")
        self.seed = int(env_cfg.get("seed", 0) if seed is None else seed)
        if num_workers is None:
            num_workers = env_cfg.get("num_workers")
        if num_workers is None:
            num_workers = available_cores()
        integer = isinstance(num_workers, int | np.integer) and not isinstance(num_workers, bool)
        if not integer or num_workers < 0:
            raise RealIkeaError(
                f"env.num_workers={num_workers!r}: use null (one per core), 0 (in-process) or more"
            )
        self.num_workers = min(int(num_workers), self.num_envs)
        if step_timeout is None:
            step_timeout = env_cfg.get("step_timeout")
        self.num_actions = int(task_factory.action_size)
        self.obs_size = int(task_factory.observation_size)
        self._iteration = 0
        self._closed = False
        self._steps = np.zeros(self.num_envs, np.int64)  # per-env steps in the current episode
        self._returns = np.zeros(self.num_envs)
        self._moves = np.zeros(self.num_envs, np.int64)  # reassignments per env
        sizes = (self.num_envs, self.num_workers, self.obs_size, self.num_actions)
        _, size = shared.layout(*sizes)
        if self.num_workers == 0:
            self._buffer = bytearray(size)
            self._a = shared.views(self._buffer, *sizes)
            seeds = self._seeds(range(self.num_envs), 0)
            self._backend = InProcess(task_factory, cfg, self.configurations, seeds, self._a, 0)
        else:
            self._buffer = spawn_context().RawArray("b", size)
            self._a = shared.views(self._buffer, *sizes)
            self._backend = Processes(
                task_factory, OmegaConf.to_container(cfg, resolve=True), self.configurations,
                self._seeds, self._buffer, sizes, self.num_workers,
                None if step_timeout is None else float(step_timeout), lambda: self._iteration,
            )  # fmt: skip
        self.horizons = np.asarray(self._backend.horizons, np.int64)
        self.horizon = int(self.horizons.max())
        self._obs = self._a["obs"].copy()

    @classmethod
    def from_config(cls, cfg: DictConfig, **kwargs) -> EnvPool:
        """`cfg.env.num_envs` configurations of the `asset` group (built if missing)."""
        num_envs = int(cfg.env.num_envs)
        if num_envs < 1:
            raise RealIkeaError(f"env.num_envs={num_envs}: use 1 or more")
        paths = training_configurations(cfg, num_envs, int(cfg.env.seed))
        return cls(cfg, paths, **kwargs)

    def _seeds(self, env_ids, generation: int) -> list[int]:
        """env i is seeded seed + i; a restarted worker's envs get fresh, still unique seeds."""
        return [self.seed + i + generation * self.num_envs for i in env_ids]

    def reassign(self, moves: dict[int, Path | str]) -> None:
        """Move envs to other configurations ({env id: MJCF}); each switches when its current
        episode ends (or at its next `reset`), with a fresh seed."""
        self._check_open()
        moves = {int(i): Path(p) for i, p in moves.items()}
        bad = {i: str(p) for i, p in moves.items() if not 0 <= i < self.num_envs or not p.is_file()}
        if bad:
            raise RealIkeaError(
                f"reassign: env ids lie in [0, {self.num_envs}) and MJCFs exist; got {bad}"
            )
        seeded = {}
        for i, path in moves.items():
            self._moves[i] += 1
            seeded[i] = (str(path), self.seed + i + self.num_envs * (RESEED + int(self._moves[i])))
            self.configurations[i] = path
        self._backend.reassign(seeded)

    # --- the vectorized env -----------------------------------------------------------------------
    @property
    def obs(self) -> np.ndarray:
        """The current observation of every env (num_envs, obs_size)."""
        return self._obs.copy()

    @property
    def counters(self) -> dict[str, int]:
        counts = self._a["counters"].sum(axis=0)
        out = {"worker_restarts": self._backend.restarts}
        out.update({name: int(counts[k]) for k, name in enumerate(shared.COUNTERS)})
        return out

    @property
    def iteration(self) -> int:
        return self._iteration

    def set_iteration(self, iteration: int) -> None:
        """The training iteration for the two-phase randomization (applies from each next reset)."""
        self._check_open()
        self._iteration = int(iteration)
        self._backend.set_iteration(self._iteration)

    def reset(self, env_ids: Sequence[int] | None = None) -> np.ndarray:
        """Start new episodes (all envs, or the given ones); returns every env's observation."""
        self._check_open()
        ids = list(range(self.num_envs)) if env_ids is None else [int(i) for i in env_ids]
        if any(i < 0 or i >= self.num_envs for i in ids):
            raise RealIkeaError(f"env ids must lie in [0, {self.num_envs}), got {ids}")
        self._backend.reset(None if env_ids is None else ids)
        self._steps[ids] = 0
        self._returns[ids] = 0.0
        self._obs = self._a["obs"].copy()
        return self._obs.copy()

    def facts(self, env_ids: Sequence[int]) -> list:
        """The facts of the given envs' current episodes (for scripted policies)."""
        self._check_open()
        ids = [int(i) for i in env_ids]
        found = self._backend.facts(ids)
        return [found[i] for i in ids]

    def step(self, actions) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        """One control step of every env (see the class docstring for what it returns)."""
        self._check_open()
        actions = np.asarray(actions, dtype=np.float64)
        if actions.shape != (self.num_envs, self.num_actions):
            raise RealIkeaError(
                f"actions must have shape ({self.num_envs}, {self.num_actions}), "
                f"got {actions.shape}"
            )
        a = self._a
        a["action"][:] = actions
        episodes, lost = self._backend.step()
        for w in lost:  # the restarted worker has written its envs' new first observations
            for i in w.env_ids:
                a["final_obs"][i] = self._obs[i]
                a["reward"][i], a["terminated"][i], a["truncated"][i] = 0.0, False, True
                episodes.append({"env": i, "termination": "worker_crash"})
        reward = a["reward"].copy()
        terminated, truncated = a["terminated"].copy(), a["truncated"].copy()
        self._steps += 1
        self._returns += reward
        for e in episodes:  # what the learner saw of each episode, however it ended
            e["episode_steps"] = int(self._steps[e["env"]])
            e["episode_return"] = float(self._returns[e["env"]])
        done = terminated | truncated
        self._steps[done] = 0
        self._returns[done] = 0.0
        self._obs = a["obs"].copy()
        info = {
            "final_obs": np.where(done[:, None], a["final_obs"], self._obs),
            "episodes": sorted(episodes, key=lambda e: e["env"]),
        }
        return self._obs.copy(), reward, terminated, truncated, info

    # --- lifetime ---------------------------------------------------------------------------------
    def _check_open(self) -> None:
        if self._closed:
            raise RealIkeaError("the env pool is closed")

    @property
    def worker_pids(self) -> list[int]:
        """Process ids of the workers (empty in-process)."""
        return self._backend.pids

    def close(self) -> None:
        """Stop the workers (idempotent)."""
        if not self._closed:
            self._closed = True
            self._backend.close()

    def __enter__(self) -> EnvPool:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
