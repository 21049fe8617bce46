"""N opening tasks stepped in parallel on all cores, with auto-reset, seeding and self-healing.

This module is the only code in the project that knows about processes. Design (measured in
experiments/bench_pool.md): about 40 % of a control step is the task's Python (mink IK, reward,
observation), so threading only the physics substeps (`mujoco.rollout` releases the GIL) would
leave that serial (Amdahl: about 1.4x on 2 cores, against 2x). Instead each worker process
owns a contiguous slice of the envs and runs whole control steps (IK + physics + reward +
observation) locally.
Actions, observations, rewards and flags live in one shared-memory block; the per-step signal is
one small pipe message per worker, which carries back only the infos of episodes that ended.
Workers are started with `spawn` (CoACD/OpenMP state does not survive fork).

Robustness, all counted in `pool.counters`:
- a worker that dies (or exceeds `step_timeout`) is restarted; its envs start new episodes
  (`worker_restarts`); the lost episodes are reported with termination "worker_crash";
- physics divergence (the task's own check, MuJoCo's instability warnings, a MuJoCo fatal error,
  or any non-finite observation or reward) ends that episode with zero reward and resets the env
  (`divergence_resets`);
- a non-finite action resets that env instead of being stepped (`bad_action_resets`).
A diverged episode ends `terminated` with zero reward; one cut short by the pool (worker crash,
bad action) ends `truncated`. Neither carries an `outcome` (they are counted instead).
A Python exception inside a task is a bug and is raised with the worker's traceback.

`num_workers=0` runs everything in the calling process (debugging, tests). With workers, a script
that builds a pool needs the `if __name__ == "__main__":` guard (spawn re-imports the main module).
"""

from __future__ import annotations

import contextlib
import math
import multiprocessing as mp
import os
import signal
import time
import traceback
import weakref
from collections.abc import Sequence
from dataclasses import dataclass, field
from multiprocessing import connection
from pathlib import Path

import mujoco
import numpy as np
from omegaconf import DictConfig, OmegaConf

from realikea.assets.library import training_configurations
from realikea.errors import RealIkeaError
from realikea.spawn import spawn_context
from realikea.tasks import observations
from realikea.tasks.contacts import SUMMARY_KEYS
from realikea.tasks.open_task import ACTION_SIZE, OpenTask

OBS_SIZE = observations.SIZE
COUNTERS = ("divergence_resets", "bad_action_resets")  # counted inside the workers
# CPU seconds (the worker thread's own, unaffected by other jobs) per part inside a worker, summed
# over its envs; the parts of a step ("apply", "ik", "simulate", "evaluate", "observe") only when
# the pool is built with profile=True (a CPU-clock read costs about 0.5 us); "busy_wall" and
# "last_busy" are wall seconds of all steps and of the latest command
TIMERS = (
    "apply", "ik", "simulate", "evaluate", "observe", "reset", "busy", "busy_wall", "last_busy",
    "steps",
)  # fmt: skip
_T = {name: k for k, name in enumerate(TIMERS)}
_C = {name: k for k, name in enumerate(COUNTERS)}
_STARTUP_TIMEOUT = 600.0  # s for a worker to build its scenes (first compile of many meshes)
_RESTART_ATTEMPTS = 3


# --- shared arrays ------------------------------------------------------------------------------
def _fields(num_envs: int, num_workers: int) -> tuple[tuple[str, tuple, type], ...]:
    n, w = num_envs, max(num_workers, 1)
    return (
        ("action", (n, ACTION_SIZE), np.float64),
        ("obs", (n, OBS_SIZE), np.float64),
        ("final_obs", (n, OBS_SIZE), np.float64),
        ("reward", (n,), np.float64),
        ("terminated", (n,), np.bool_),
        ("truncated", (n,), np.bool_),
        ("opening", (n,), np.float64),
        ("stage", (n,), np.int64),
        ("ik_ok", (n,), np.bool_),
        ("counters", (w, len(COUNTERS)), np.int64),
        ("timers", (w, len(TIMERS)), np.float64),
    )


def _layout(num_envs: int, num_workers: int) -> tuple[dict[str, tuple[int, tuple, type]], int]:
    """Byte offset, shape and dtype of every shared array (64-byte aligned), and the total size."""
    out, offset = {}, 0
    for name, shape, dtype in _fields(num_envs, num_workers):
        out[name] = (offset, shape, dtype)
        nbytes = int(np.prod(shape)) * np.dtype(dtype).itemsize
        offset += -(-nbytes // 64) * 64
    return out, max(offset, 64)


def _views(buffer, num_envs: int, num_workers: int) -> dict[str, np.ndarray]:
    layout, _ = _layout(num_envs, num_workers)
    return {
        name: np.frombuffer(buffer, dtype=dtype, count=int(np.prod(shape)), offset=off).reshape(
            shape
        )
        for name, (off, shape, dtype) in layout.items()
    }


# --- the envs of one worker (also the in-process implementation) --------------------------------
def _timed(fn, timers: np.ndarray, slot: int):
    def wrapper(*args, **kwargs):
        start = time.thread_time()
        try:
            return fn(*args, **kwargs)
        finally:
            timers[slot] += time.thread_time() - start

    return wrapper


def _no_clock() -> float:
    return 0.0


class _EnvSlice:
    """The envs one worker owns: steps them and writes their rows of the shared arrays."""

    def __init__(self, cfg, paths, seeds, env_ids, arrays, worker, iteration, profile):
        self.ids = [int(i) for i in env_ids]
        self.tasks = [OpenTask(cfg, Path(p), int(s)) for p, s in zip(paths, seeds, strict=True)]
        self.a = arrays
        self.counters, self.timers = arrays["counters"][worker], arrays["timers"][worker]
        self.profile = bool(profile)
        if profile:  # per-part timing for the benchmark: IK and observation inside the task
            for task in self.tasks:
                task.ik.solve = _timed(task.ik.solve, self.timers, _T["ik"])
                task.observe = _timed(task.observe, self.timers, _T["observe"])
        self.set_iteration(iteration)
        self.reset()

    def info(self) -> dict:
        return {
            "horizon": [t.horizon for t in self.tasks],
            "joint_type": [t.joint_type for t in self.tasks],
        }

    def facts(self, env_ids) -> dict:
        """The current episode's SceneFacts of the given global env ids that this slice owns."""
        wanted = {int(i) for i in env_ids}
        return {i: t.facts() for t, i in zip(self.tasks, self.ids, strict=True) if i in wanted}

    def set_iteration(self, iteration: int) -> None:
        for task in self.tasks:
            task.iteration = int(iteration)

    def reset(self, env_ids=None) -> None:
        """Start new episodes for the given global env ids (all of this slice's by default)."""
        start = time.perf_counter()
        wanted = None if env_ids is None else {int(i) for i in env_ids}
        for task, i in zip(self.tasks, self.ids, strict=True):
            if wanted is None or i in wanted:
                self._reset_one(task, i)
        self.timers[_T["last_busy"]] = time.perf_counter() - start

    def _reset_one(self, task: OpenTask, i: int) -> None:
        start = time.thread_time()
        self.a["obs"][i] = task.reset()
        self.timers[_T["reset"]] += time.thread_time() - start

    def _end(self, task, i, final_obs, reward, terminated, truncated, record) -> dict:
        """Write the last step of an episode, keep its final observation and start the next one."""
        a = self.a
        a["final_obs"][i] = final_obs
        a["reward"][i], a["terminated"][i], a["truncated"][i] = reward, terminated, truncated
        record["env"] = i
        self._reset_one(task, i)
        return record

    @staticmethod
    def _aborted(task: OpenTask, termination: str) -> dict:
        opening = task.opening
        return {"termination": termination, "opening": opening if math.isfinite(opening) else 0.0}

    def step(self) -> list[dict]:
        """One control step of every env; returns the infos of the episodes that ended."""
        a, timers, profile = self.a, self.timers, self.profile
        actions, obs, rewards, opening, stage, ik_ok = (
            a[k] for k in ("action", "obs", "reward", "opening", "stage", "ik_ok")
        )
        clock = time.thread_time if profile else _no_clock
        begin, begin_cpu = time.perf_counter(), time.thread_time()
        finite_actions = np.isfinite(actions[self.ids]).all(axis=1).tolist()  # one check for all
        ended = []
        for task, i, finite_action in zip(self.tasks, self.ids, finite_actions, strict=True):
            ik_ok[i] = False
            stage[i] = task.state.stage
            if not finite_action:
                self.counters[_C["bad_action_resets"]] += 1
                record = self._aborted(task, "bad_action")
                opening[i] = record["opening"]
                ended.append(self._end(task, i, obs[i].copy(), 0.0, False, True, record))
                continue
            t0 = clock()
            ok = task.apply_action(actions[i])
            t1 = clock()
            try:
                task.simulate()
                t2 = clock()
                result = task.evaluate(ok)
                fatal = False
            except mujoco.FatalError:
                t2, result, fatal = clock(), None, True
            if profile:
                t3 = clock()
                timers[_T["apply"]] += t1 - t0
                timers[_T["simulate"]] += t2 - t1
                timers[_T["evaluate"]] += t3 - t2
            finite = not fatal and np.isfinite(result.obs).all() and math.isfinite(result.reward)
            if fatal or not finite or result.info["diverged"]:
                self.counters[_C["divergence_resets"]] += 1
                record = self._aborted(task, "diverged")
                opening[i] = record["opening"]
                ended.append(self._end(task, i, np.zeros(OBS_SIZE), 0.0, True, False, record))
                continue
            info = result.info
            opening[i], stage[i], ik_ok[i] = info["opening"], info["stage"], ok
            if result.terminated or result.truncated:
                record = {k: info[k] for k in _EPISODE_KEYS if k in info}
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
        busy = time.perf_counter() - begin
        timers[_T["busy"]] += time.thread_time() - begin_cpu
        timers[_T["busy_wall"]] += busy
        timers[_T["last_busy"]] = busy
        timers[_T["steps"]] += len(self.tasks)
        return ended


_EPISODE_KEYS = ("outcome", "termination", "opening", "reward_terms", *SUMMARY_KEYS)


def _worker_main(conn, buffer, num_envs, num_workers, cfg, paths, seeds, env_ids, worker, it, prof):
    """A worker process: build its envs, then serve commands until told to close."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the pool's to handle
    try:
        arrays = _views(buffer, num_envs, num_workers)
        envs = _EnvSlice(OmegaConf.create(cfg), paths, seeds, env_ids, arrays, worker, it, prof)
        conn.send(("ready", envs.info()))
    except BaseException:
        conn.send(("error", traceback.format_exc()))
        return
    while True:
        try:
            command, argument = conn.recv()
        except (EOFError, OSError):  # the pool is gone
            return
        try:
            if command == "step":
                conn.send(("ok", envs.step()))
            elif command == "reset":
                envs.reset(argument)
                conn.send(("ok", None))
            elif command == "facts":
                conn.send(("ok", envs.facts(argument)))
            elif command == "iteration":  # no reply: pipe order puts it before the next step
                envs.set_iteration(argument)
            elif command == "close":
                conn.send(("ok", None))
                return
        except Exception:
            conn.send(("error", traceback.format_exc()))


# --- the pool -----------------------------------------------------------------------------------
@dataclass
class _Worker:
    index: int
    env_ids: list[int]
    generation: int = 0
    process: mp.process.BaseProcess | None = None
    conn: connection.Connection | None = None
    info: dict = field(default_factory=dict)


@contextlib.contextmanager
def _single_threaded_children():
    """Children inherit the environment at spawn: one BLAS/OpenMP thread per worker process."""
    names = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
    saved = {k: os.environ.get(k) for k in names}
    for k in names:
        os.environ.setdefault(k, "1")
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _stop(workers: list[_Worker]) -> None:
    """Ask every worker to close, then make sure it is gone (no zombies)."""
    for w in workers:
        with contextlib.suppress(Exception):
            if w.process is not None and w.process.is_alive():
                w.conn.send(("close", None))
    for w in workers:
        if w.process is None:
            continue
        w.process.join(timeout=5)
        if w.process.is_alive():
            w.process.kill()
            w.process.join(timeout=5)
        with contextlib.suppress(Exception):
            w.conn.close()
        with contextlib.suppress(Exception):
            w.process.close()
        w.process = None


def available_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


class EnvPool:
    """`len(configurations)` opening tasks (env i on configurations[i], seeded seed + i).

    `step(actions)` returns (obs, reward, terminated, truncated, info) as numpy arrays over the
    envs. An env whose episode ended is reset at once: `obs` holds its new episode's first
    observation, `info["final_obs"]` the last one of the finished episode, and
    `info["episodes"]` one dict per finished episode (env, termination, episode_steps,
    episode_return, opening, and outcome when the task itself ended it). `info` also holds the
    per-env `opening`, `stage` and `ik_ok` of the step.
    """

    def __init__(
        self,
        cfg: DictConfig,
        configurations: Sequence[Path | str],
        seed: int | None = None,
        num_workers: int | None = None,
        step_timeout: float | None = None,
        profile: bool = False,
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
        self.step_timeout = None if step_timeout is None else float(step_timeout)
        self.num_actions, self.obs_size = ACTION_SIZE, OBS_SIZE
        self.profile = profile
        self._iteration = 0
        self._restarts = 0
        self._closed = False
        self._steps = np.zeros(self.num_envs, np.int64)  # per-env steps in the current episode
        self._returns = np.zeros(self.num_envs)
        self._main_timers = {"wall": 0.0, "transfer": 0.0, "steps": 0}
        _, size = _layout(self.num_envs, self.num_workers)
        self._cfg_container = OmegaConf.to_container(cfg, resolve=True)
        self._workers: list[_Worker] = []
        if self.num_workers == 0:
            self._buffer = bytearray(size)
            self._a = _views(self._buffer, self.num_envs, 0)
            ids = list(range(self.num_envs))
            self._local = _EnvSlice(
                cfg, self.configurations, self._seeds(ids, 0), ids, self._a, 0, 0, profile
            )
            info = self._local.info()
        else:
            self._local = None
            self._ctx = spawn_context()
            self._buffer = self._ctx.RawArray("b", size)
            self._a = _views(self._buffer, self.num_envs, self.num_workers)
            slices = np.array_split(np.arange(self.num_envs), self.num_workers)
            self._workers = [_Worker(k, [int(i) for i in s]) for k, s in enumerate(slices)]
            self._finalizer = weakref.finalize(self, _stop, self._workers)
            try:
                for w in self._workers:
                    self._spawn(w)
                for w in self._workers:
                    self._await_ready(w)
            except BaseException:
                self.close()
                raise
            info = {"horizon": [], "joint_type": []}
            for w in self._workers:
                for key in info:
                    info[key] += w.info[key]
        self.horizons = np.asarray(info["horizon"], np.int64)
        self.joint_types = list(info["joint_type"])
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

    # --- worker processes -----------------------------------------------------------------------
    def _seeds(self, env_ids, generation: int) -> list[int]:
        """env i is seeded seed + i; a restarted worker's envs get fresh, still unique seeds."""
        return [self.seed + i + generation * self.num_envs for i in env_ids]

    def _spawn(self, w: _Worker) -> None:
        parent, child = self._ctx.Pipe()
        args = (
            child, self._buffer, self.num_envs, self.num_workers, self._cfg_container,
            [str(self.configurations[i]) for i in w.env_ids], self._seeds(w.env_ids, w.generation),
            w.env_ids, w.index, self._iteration, self.profile,
        )  # fmt: skip
        process = self._ctx.Process(
            target=_worker_main, args=args, daemon=True, name=f"realikea-env-worker-{w.index}"
        )
        with _single_threaded_children():
            process.start()
        child.close()
        w.process, w.conn = process, parent

    def _await_ready(self, w: _Worker) -> None:
        ready = connection.wait([w.conn, w.process.sentinel], timeout=_STARTUP_TIMEOUT)
        if w.conn in ready or w.conn.poll():
            try:
                kind, payload = w.conn.recv()
            except (EOFError, OSError):
                kind, payload = "error", "the worker exited while building its envs"
        elif not ready:
            kind, payload = "error", f"no answer within {_STARTUP_TIMEOUT:.0f} s"
        else:
            kind, payload = "error", f"the worker exited with code {w.process.exitcode}"
        if kind != "ready":
            raise RealIkeaError(f"env worker {w.index} failed to start:\n{payload}")
        w.info = payload

    def _restart(self, w: _Worker) -> None:
        """Replace a dead (or hung) worker; its envs start new episodes."""
        self._restarts += 1
        if w.process is not None:
            if w.process.is_alive():
                w.process.kill()
            w.process.join(timeout=10)
            with contextlib.suppress(Exception):
                w.conn.close()
        for attempt in range(_RESTART_ATTEMPTS):
            w.generation += 1
            self._spawn(w)
            try:
                self._await_ready(w)
                return
            except RealIkeaError:
                w.process.kill()
                w.process.join(timeout=10)
                if attempt == _RESTART_ATTEMPTS - 1:
                    raise

    def _command(self, command: str, argument=None, workers=None) -> tuple[dict, list[_Worker]]:
        """Send a command, wait for the replies; returns them and the workers that were lost."""
        workers = self._workers if workers is None else workers
        lost, pending = [], []
        for w in workers:
            try:
                w.conn.send((command, argument))
                pending.append(w)
            except (BrokenPipeError, ConnectionResetError, OSError):
                lost.append(w)
        replies = {}
        deadline = None if self.step_timeout is None else time.monotonic() + self.step_timeout
        while pending:
            waiting = {w.conn: w for w in pending} | {w.process.sentinel: w for w in pending}
            timeout = None if deadline is None else max(deadline - time.monotonic(), 0.0)
            ready = connection.wait(list(waiting), timeout=timeout)
            if not ready:  # hung workers: treated like dead ones
                lost += pending
                break
            for obj in ready:
                w = waiting[obj]
                if w not in pending:
                    continue
                pending.remove(w)
                try:
                    if not w.conn.poll():
                        raise EOFError
                    kind, payload = w.conn.recv()
                except (EOFError, OSError):
                    lost.append(w)
                    continue
                if kind == "error":  # a bug in a task: stop cleanly and show where
                    self.close()
                    raise RealIkeaError(f"env worker {w.index} raised:\n{payload}")
                replies[w.index] = payload
        for w in lost:
            self._restart(w)
        return replies, lost

    # --- the vectorized env -----------------------------------------------------------------------
    @property
    def obs(self) -> np.ndarray:
        """The current observation of every env (num_envs, obs_size)."""
        return self._obs.copy()

    @property
    def counters(self) -> dict[str, int]:
        counts = self._a["counters"].sum(axis=0)
        out = {"worker_restarts": self._restarts}
        out.update({name: int(counts[k]) for k, name in enumerate(COUNTERS)})
        return out

    @property
    def iteration(self) -> int:
        return self._iteration

    def set_iteration(self, iteration: int) -> None:
        """The training iteration for the two-phase randomization (applies from each next reset)."""
        self._check_open()
        self._iteration = int(iteration)
        if self._local is not None:
            self._local.set_iteration(self._iteration)
            return
        for w in self._workers:  # no reply; a dead worker restarts with the current iteration
            with contextlib.suppress(BrokenPipeError, ConnectionResetError, OSError):
                w.conn.send(("iteration", self._iteration))

    def reset(self, env_ids: Sequence[int] | None = None) -> np.ndarray:
        """Start new episodes (all envs, or the given ones); returns every env's observation."""
        self._check_open()
        ids = range(self.num_envs) if env_ids is None else [int(i) for i in env_ids]
        if any(i < 0 or i >= self.num_envs for i in ids):
            raise RealIkeaError(f"env ids must lie in [0, {self.num_envs}), got {list(ids)}")
        if self._local is not None:
            self._local.reset(None if env_ids is None else ids)
        else:
            wanted = set(ids)
            owners = [w for w in self._workers if wanted & set(w.env_ids)]
            self._command("reset", None if env_ids is None else sorted(wanted), owners)
        self._steps[list(ids)] = 0
        self._returns[list(ids)] = 0.0
        self._obs = self._a["obs"].copy()
        return self._obs.copy()

    def facts(self, env_ids: Sequence[int]) -> list:
        """The SceneFacts of the given envs' current episodes (for scripted policies)."""
        self._check_open()
        ids = [int(i) for i in env_ids]
        if self._local is not None:
            found = self._local.facts(ids)
        else:
            wanted = set(ids)
            owners = [w for w in self._workers if wanted & set(w.env_ids)]
            replies, lost = self._command("facts", ids, owners)
            if lost:
                raise RealIkeaError("an env worker was lost while reading scene facts")
            found = {i: f for reply in replies.values() for i, f in reply.items()}
        return [found[i] for i in ids]

    def step(self, actions) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        """One control step of every env (see the class docstring for what it returns)."""
        self._check_open()
        actions = np.asarray(actions, dtype=np.float64)
        if actions.shape != (self.num_envs, ACTION_SIZE):
            raise RealIkeaError(
                f"actions must have shape ({self.num_envs}, {ACTION_SIZE}), got {actions.shape}"
            )
        a = self._a
        a["action"][:] = actions
        start = time.perf_counter()
        if self._local is not None:
            episodes, lost = self._local.step(), []
            busy = self._local.timers[_T["last_busy"]]
        else:
            replies, lost = self._command("step")
            episodes = [e for k in sorted(replies) for e in replies[k]]
            alive = [w.index for w in self._workers if w not in lost]
            busy = max((a["timers"][k, _T["last_busy"]] for k in alive), default=0.0)
        for w in lost:  # the restarted worker has written its envs' new first observations
            for i in w.env_ids:
                a["final_obs"][i] = self._obs[i]
                a["reward"][i], a["terminated"][i], a["truncated"][i] = 0.0, False, True
                a["opening"][i] = self._obs[i][_OPENING]
                a["ik_ok"][i] = False
                opening = float(a["opening"][i])
                episodes.append({"env": i, "termination": "worker_crash", "opening": opening})
        wall = time.perf_counter() - start
        self._main_timers["wall"] += wall
        self._main_timers["transfer"] += max(wall - busy, 0.0)
        self._main_timers["steps"] += 1

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
            "opening": a["opening"].copy(),
            "stage": a["stage"].copy(),
            "ik_ok": a["ik_ok"].copy(),
        }
        return self._obs.copy(), reward, terminated, truncated, info

    # --- timing (benchmark) ---------------------------------------------------------------------
    def timing(self) -> dict[str, float]:
        """Seconds per part (TIMERS) summed over the workers since the last `reset_timing`, plus
        the main process's wall time in `step` and the part of it the workers did not spend
        stepping ("transfer": signalling, copies, scheduling)."""
        rows = self._a["timers"]
        out = {name: float(rows[:, k].sum()) for k, name in enumerate(TIMERS)}
        out.pop("last_busy")
        out.update({f"main_{k}": float(v) for k, v in self._main_timers.items()})
        out["workers"] = max(self.num_workers, 1)
        return out

    def reset_timing(self) -> None:
        self._a["timers"][:] = 0.0
        self._main_timers = {"wall": 0.0, "transfer": 0.0, "steps": 0}

    # --- lifetime ---------------------------------------------------------------------------------
    def _check_open(self) -> None:
        if self._closed:
            raise RealIkeaError("the env pool is closed")

    @property
    def worker_pids(self) -> list[int]:
        """Process ids of the workers (empty in-process)."""
        return [w.process.pid for w in self._workers if w.process is not None]

    def close(self) -> None:
        """Stop the workers (idempotent)."""
        if self._closed:
            return
        self._closed = True
        if self._workers:
            self._finalizer()

    def __enter__(self) -> EnvPool:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


_OPENING = observations.slices()["opening"].start
