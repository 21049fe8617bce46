"""The env pool benchmark's workload: a scripted approach-grasp-pull policy with noise, recorded
once (actions, controls, physics states) so every way of stepping replays the same work; and the
instrumented task that times each part of a control step (`bench_pool.py`)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import mujoco
import numpy as np

from realikea.pool.env_pool import EnvPool
from realikea.tasks import observations
from realikea.tasks.open_task import OpenTask

SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS
S = observations.slices()


def scripted(obs: np.ndarray, k: np.ndarray, rng: np.random.Generator, noise: float) -> np.ndarray:
    """Approach 6 cm in front of the handle, move onto it, close, pull; plus Gaussian noise."""
    rel = obs[:, S["handle_from_tcp"]].copy()
    goal = np.where((k < 30)[:, None], rel + np.array([0.06, 0.0, 0.0]), rel)
    goal[k >= 55] = (0.05, 0.0, 0.0)
    a = np.zeros((len(obs), 5))
    a[:, 1:4] = np.clip(goal / 0.01, -1.0, 1.0)
    a[:, 4] = np.where(k < 45, 1.0, -1.0)
    return np.clip(a + noise * rng.standard_normal(a.shape), -1.0, 1.0)


class Recording:
    """Actions, controls, chunk-start states and warm starts of an in-process run."""

    def __init__(self, cfg, paths, seed, steps, chunk, warmup, noise=0.3):
        n = len(paths)
        self.tasks = [OpenTask(cfg, p, seed + i) for i, p in enumerate(paths)]
        self.steps, self.chunk, self.decimation = steps, chunk, self.tasks[0].decimation
        nchunk = -(-steps // chunk)
        obs = np.array([t.reset() for t in self.tasks])
        k = np.zeros(n, np.int64)
        rng = np.random.default_rng(seed)
        self.actions = np.zeros((steps, n, 5))
        self.ctrl = [np.zeros((steps, t.model.nu)) for t in self.tasks]
        self.state = [np.zeros((nchunk, mujoco.mj_stateSize(t.model, SPEC))) for t in self.tasks]
        self.warm = [np.zeros((nchunk, t.model.nv)) for t in self.tasks]
        self.reset_in_chunk = np.zeros((n, nchunk), bool)
        contacts = 0
        for s in range(steps):
            a = scripted(obs, k, rng, noise)
            self.actions[s] = a
            for i, t in enumerate(self.tasks):
                if s % chunk == 0:
                    mujoco.mj_getState(t.model, t.data, self.state[i][s // chunk], SPEC)
                    self.warm[i][s // chunk] = t.data.qacc_warmstart
                ok = t.apply_action(a[i])
                self.ctrl[i][s] = t.data.ctrl
                t.simulate()
                contacts += t.data.ncon if s >= warmup else 0
                r = t.evaluate(ok)
                if r.terminated or r.truncated:
                    obs[i], k[i] = t.reset(), 0
                    self.reset_in_chunk[i, s // chunk] = True
                else:
                    obs[i], k[i] = r.obs, k[i] + 1
        self.mean_contacts = contacts / ((steps - warmup) * n)


def cpu_seconds(pid: int) -> float:
    """User + system CPU seconds of a process so far (/proc/<pid>/stat)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def run_pool(cfg, paths, seed, actions, warmup, workers=None):
    """Env-steps/s of the pool over actions[warmup:] (the first `warmup` steps untimed), its
    startup, and the timed window's wall seconds, steps and each worker's CPU seconds."""
    start = time.perf_counter()
    pool = EnvPool(cfg, paths, seed=seed, num_workers=workers)
    startup = time.perf_counter() - start
    try:
        for a in actions[:warmup]:
            pool.step(a)
        cpu0 = [cpu_seconds(pid) for pid in pool.worker_pids]
        start = time.perf_counter()
        for a in actions[warmup:]:
            pool.step(a)
        elapsed = time.perf_counter() - start
        cpu = [cpu_seconds(pid) - c for pid, c in zip(pool.worker_pids, cpu0, strict=True)]
        window = {"wall": elapsed, "steps": len(actions) - warmup, "worker_cpu": cpu}
        return actions[warmup:].size // 5 / elapsed, startup, window
    finally:
        pool.close()


PARTS = ("apply", "ik", "simulate", "evaluate", "observe", "reset")


class ProfiledTask(OpenTask):
    """The opening task with the thread CPU time of each part summed in `ProfiledTask.seconds`
    (in the process that steps it: the benchmark runs it in-process)."""

    seconds = dict.fromkeys(PARTS, 0.0)

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.ik.solve = self._timed("ik", self.ik.solve)

    @classmethod
    def _timed(cls, part, fn):
        def wrapper(*args, **kwargs):
            start = time.thread_time()
            try:
                return fn(*args, **kwargs)
            finally:
                cls.seconds[part] += time.thread_time() - start

        return wrapper

    def apply_action(self, action):
        return self._timed("apply", super().apply_action)(action)

    def simulate(self):
        return self._timed("simulate", super().simulate)()

    def evaluate(self, ik_ok):
        return self._timed("evaluate", super().evaluate)(ik_ok)

    def observe(self):
        return self._timed("observe", super().observe)()

    def reset(self):
        return self._timed("reset", super().reset)()


def profile_parts(cfg, paths, seed, actions, warmup) -> tuple[dict, float]:
    """CPU seconds per part over actions[warmup:] in-process, and the pool's whole step CPU."""
    with EnvPool(cfg, paths, seed=seed, num_workers=0, task_factory=ProfiledTask) as pool:
        for a in actions[:warmup]:
            pool.step(a)
        ProfiledTask.seconds = dict.fromkeys(PARTS, 0.0)
        start = time.thread_time()
        for a in actions[warmup:]:
            pool.step(a)
        busy = time.thread_time() - start
    return dict(ProfiledTask.seconds), busy
