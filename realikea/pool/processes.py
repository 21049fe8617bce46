"""Worker processes for the env pool: each owns a contiguous slice of the envs and runs whole
control steps; a worker that dies or stops answering is restarted with fresh episodes.

This is the only code in the project that knows about processes. Workers are started with
`spawn` (CoACD/OpenMP state does not survive fork); the per-step signal is one small pipe message
per worker, which carries back only the records of episodes that ended. A Python exception
inside a task is a bug: the pool stops and raises it with the worker's traceback.
"""

from __future__ import annotations

import contextlib
import multiprocessing as mp
import os
import signal
import time
import traceback
import weakref
from dataclasses import dataclass, field
from multiprocessing import connection

import numpy as np
from omegaconf import OmegaConf

from realikea.errors import RealIkeaError
from realikea.pool import shared
from realikea.pool.env_slice import EnvSlice
from realikea.spawn import spawn_context

STARTUP_TIMEOUT = 600.0  # s for a worker to build its scenes (first compile of many meshes)
RESTART_ATTEMPTS = 3


def available_cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def _worker_main(conn, buffer, sizes, task_factory, cfg, paths, seeds, env_ids, worker, it):
    """A worker process: build its envs, then serve commands until told to close."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the pool's to handle
    try:
        arrays = shared.views(buffer, *sizes)
        envs = EnvSlice(task_factory, OmegaConf.create(cfg), paths, seeds, env_ids, arrays,
                        worker, it)  # fmt: skip
        conn.send(("ready", envs.horizons()))
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
            elif command == "reassign":  # no reply, as for the iteration
                envs.reassign(argument)
            elif command == "close":
                conn.send(("ok", None))
                return
        except Exception:
            conn.send(("error", traceback.format_exc()))


@dataclass
class Worker:
    index: int
    env_ids: list[int]
    generation: int = 0
    process: mp.process.BaseProcess | None = None
    conn: connection.Connection | None = None
    horizons: list[int] = field(default_factory=list)


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


def _stop(workers: list[Worker]) -> None:
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


class Processes:
    """`num_workers` worker processes over contiguous slices of the envs (see the module doc).

    `seeds(env_ids, generation)` gives the seeds of a (re)started worker's envs; `iteration()`
    the current training iteration a restarted worker starts from."""

    def __init__(self, task_factory, cfg, paths, seeds, buffer, sizes, num_workers, timeout,
                 iteration):  # fmt: skip
        self.task_factory, self.cfg, self.paths = task_factory, cfg, [str(p) for p in paths]
        self.seeds, self.buffer, self.sizes = seeds, buffer, sizes
        self.timeout, self.iteration = timeout, iteration
        self.restarts = 0
        self.ctx = spawn_context()
        slices = np.array_split(np.arange(len(paths)), num_workers)
        self.workers = [Worker(k, [int(i) for i in s]) for k, s in enumerate(slices)]
        self._finalizer = weakref.finalize(self, _stop, self.workers)
        try:
            for w in self.workers:
                self._spawn(w)
            for w in self.workers:
                self._await_ready(w)
        except BaseException:
            self.close()
            raise
        self.horizons = [h for w in self.workers for h in w.horizons]

    @property
    def pids(self) -> list[int]:
        return [w.process.pid for w in self.workers if w.process is not None]

    def _spawn(self, w: Worker) -> None:
        parent, child = self.ctx.Pipe()
        args = (
            child, self.buffer, self.sizes, self.task_factory, self.cfg,
            [self.paths[i] for i in w.env_ids], self.seeds(w.env_ids, w.generation), w.env_ids,
            w.index, self.iteration(),
        )  # fmt: skip
        process = self.ctx.Process(
            target=_worker_main, args=args, daemon=True, name=f"realikea-env-worker-{w.index}"
        )
        with _single_threaded_children():
            process.start()
        child.close()
        w.process, w.conn = process, parent

    def _await_ready(self, w: Worker) -> None:
        ready = connection.wait([w.conn, w.process.sentinel], timeout=STARTUP_TIMEOUT)
        if w.conn in ready or w.conn.poll():
            try:
                kind, payload = w.conn.recv()
            except (EOFError, OSError):
                kind, payload = "error", "the worker exited while building its envs"
        elif not ready:
            kind, payload = "error", f"no answer within {STARTUP_TIMEOUT:.0f} s"
        else:
            kind, payload = "error", f"the worker exited with code {w.process.exitcode}"
        if kind != "ready":
            raise RealIkeaError(f"env worker {w.index} failed to start:\n{payload}")
        w.horizons = payload

    def _restart(self, w: Worker) -> None:
        """Replace a dead (or hung) worker; its envs start new episodes."""
        self.restarts += 1
        if w.process is not None:
            if w.process.is_alive():
                w.process.kill()
            w.process.join(timeout=10)
            with contextlib.suppress(Exception):
                w.conn.close()
        for attempt in range(RESTART_ATTEMPTS):
            w.generation += 1
            self._spawn(w)
            try:
                self._await_ready(w)
                return
            except RealIkeaError:
                w.process.kill()
                w.process.join(timeout=10)
                if attempt == RESTART_ATTEMPTS - 1:
                    raise

    def _command(self, command: str, argument=None, workers=None) -> tuple[dict, list[Worker]]:
        """Send a command, wait for the replies; returns them and the workers that were lost
        (restarted)."""
        workers = self.workers if workers is None else workers
        lost, pending = [], []
        for w in workers:
            try:
                w.conn.send((command, argument))
                pending.append(w)
            except (BrokenPipeError, ConnectionResetError, OSError):
                lost.append(w)
        replies = {}
        deadline = None if self.timeout is None else time.monotonic() + self.timeout
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

    def _owners(self, env_ids) -> list[Worker]:
        wanted = set(env_ids)
        return [w for w in self.workers if wanted & set(w.env_ids)]

    def step(self) -> tuple[list[dict], list[Worker]]:
        replies, lost = self._command("step")
        return [e for k in sorted(replies) for e in replies[k]], lost

    def reset(self, env_ids=None) -> None:
        owners = self.workers if env_ids is None else self._owners(env_ids)
        self._command("reset", None if env_ids is None else sorted(env_ids), owners)

    def facts(self, env_ids) -> dict:
        replies, lost = self._command("facts", list(env_ids), self._owners(env_ids))
        if lost:
            raise RealIkeaError("an env worker was lost while reading scene facts")
        return {i: f for reply in replies.values() for i, f in reply.items()}

    def set_iteration(self, iteration: int) -> None:
        for w in self.workers:  # no reply; a dead worker restarts with the current iteration
            with contextlib.suppress(BrokenPipeError, ConnectionResetError, OSError):
                w.conn.send(("iteration", iteration))

    def reassign(self, moves: dict) -> None:
        """Move envs to other configurations ({env id: (MJCF, seed)}) from their next episode; a
        worker restarted later builds them there."""
        for i, (path, _) in moves.items():
            self.paths[i] = str(path)
        for w in self._owners(moves):
            with contextlib.suppress(BrokenPipeError, ConnectionResetError, OSError):
                w.conn.send(("reassign", {i: moves[i] for i in w.env_ids if i in moves}))

    def close(self) -> None:
        self._finalizer()
