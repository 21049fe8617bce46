"""The ways the env pool benchmark steps its recorded work besides the pool: the physics limit
(`mujoco.rollout` on every core), gymnasium's AsyncVectorEnv, and the physics threaded through
`mujoco.rollout` with the rest serial (`bench_pool.py`)."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor
from functools import partial

import gymnasium as gym
import mujoco
import mujoco.rollout
import numpy as np
from omegaconf import OmegaConf
from pool_workload import SPEC, Recording

from realikea.pool.gym_env import OpenTaskEnv
from realikea.tasks.open_task import OpenTask


def physics_limit(rec: Recording, threads: int, warmup: int) -> tuple[float, float]:
    """Env-steps/s of the recorded physics after `warmup` control steps, replayed with
    mujoco.rollout on `threads` threads, and the largest deviation from the recorded states."""
    n, dec, chunk = len(rec.tasks), rec.decimation, rec.chunk
    datas = [mujoco.MjData(t.model) for t in rec.tasks]
    controls = [np.repeat(c, dec, axis=0) for c in rec.ctrl]
    out = [np.zeros((1, chunk * dec, len(s[0]))) for s in rec.state]
    deviation = np.zeros(n)

    def run(i):
        m, d = rec.tasks[i].model, datas[i]
        for c in range(warmup // chunk, len(rec.state[i])):
            lo, hi = c * chunk * dec, min((c + 1) * chunk, rec.steps) * dec
            state = out[i][:, : hi - lo]
            mujoco.rollout.rollout(
                m, d, rec.state[i][c : c + 1], controls[i][None, lo:hi],
                initial_warmstart=rec.warm[i][c : c + 1], state=state,
                sensordata=np.zeros((1, hi - lo, m.nsensordata)),
            )  # fmt: skip
            if c + 1 < len(rec.state[i]) and not rec.reset_in_chunk[i, c]:
                deviation[i] = max(deviation[i], np.abs(state[0, -1] - rec.state[i][c + 1]).max())

    start = time.perf_counter()
    with ThreadPoolExecutor(threads) as ex:
        list(ex.map(run, range(n)))
    elapsed = time.perf_counter() - start
    return n * (rec.steps - warmup // chunk * chunk) / elapsed, float(deviation.max())


def async_vector(cfg, paths, seed, actions, warmup) -> tuple[float, float]:
    container = OmegaConf.to_container(cfg, resolve=True)
    fns = [partial(OpenTaskEnv, container, str(p), seed + i) for i, p in enumerate(paths)]
    start = time.perf_counter()
    envs = gym.vector.AsyncVectorEnv(
        fns, context="spawn", autoreset_mode=gym.vector.AutoresetMode.SAME_STEP
    )
    try:
        envs.reset()
        startup = time.perf_counter() - start
        for a in actions[:warmup]:
            envs.step(a.astype(np.float32))
        start = time.perf_counter()
        for a in actions[warmup:]:
            envs.step(a.astype(np.float32))
        elapsed = time.perf_counter() - start
    finally:
        envs.close()
    return actions[warmup:].size // 5 / elapsed, startup


def rollout_threaded_physics(cfg, paths, seed, actions, warmup, threads) -> float:
    """IK, reward and observation serial in Python; the physics substeps of all envs threaded
    through mujoco.rollout (the task's own MjData, left at the final state, as mj_step would)."""
    tasks = [OpenTask(cfg, p, seed + i) for i, p in enumerate(paths)]
    for t in tasks:
        t.reset()
    dec = tasks[0].decimation
    state0 = [np.zeros((1, mujoco.mj_stateSize(t.model, SPEC))) for t in tasks]
    ctrl = [np.zeros((1, dec, t.model.nu)) for t in tasks]
    warm = [np.zeros((1, t.model.nv)) for t in tasks]
    out = [np.zeros((1, dec, s.shape[1])) for s in state0]
    sens = [np.zeros((1, dec, t.model.nsensordata)) for t in tasks]

    def physics(i):
        m, d = tasks[i].model, tasks[i].data
        mujoco.mj_getState(m, d, state0[i][0], SPEC)
        ctrl[i][0, :] = d.ctrl
        warm[i][0] = d.qacc_warmstart
        mujoco.rollout.rollout(
            m, d, state0[i], ctrl[i], initial_warmstart=warm[i], state=out[i], sensordata=sens[i]
        )

    with ThreadPoolExecutor(threads) as ex:
        for s, a in enumerate(actions):
            if s == warmup:
                start = time.perf_counter()
            oks = [t.apply_action(a[i]) for i, t in enumerate(tasks)]
            list(ex.map(physics, range(len(tasks))))
            for t, ok in zip(tasks, oks, strict=True):
                r = t.evaluate(ok)
                if r.terminated or r.truncated:
                    t.reset()
        elapsed = time.perf_counter() - start
    return actions[warmup:].size // 5 / elapsed


def physics_per_step(rec: Recording, warmup: int) -> float:
    """CPU µs per physics step of the recorded run replayed with mujoco.rollout in this thread
    (thread CPU time: other jobs on the machine do not inflate it)."""
    steps, elapsed = 0, 0.0
    dec, chunk = rec.decimation, rec.chunk
    for i, t in enumerate(rec.tasks):
        d = mujoco.MjData(t.model)
        controls = np.repeat(rec.ctrl[i], dec, axis=0)
        for c in range(warmup // chunk, len(rec.state[i])):
            lo, hi = c * chunk * dec, min((c + 1) * chunk, rec.steps) * dec
            start = time.thread_time()
            mujoco.rollout.rollout(
                t.model, d, rec.state[i][c : c + 1], controls[None, lo:hi],
                initial_warmstart=rec.warm[i][c : c + 1],
            )  # fmt: skip
            elapsed += time.thread_time() - start
            steps += hi - lo
    return elapsed / steps * 1e6
