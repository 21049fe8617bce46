"""The one way this project starts worker processes: fresh interpreters (`spawn`), and a
process pool mapped over jobs with a progress bar.

CoACD's OpenMP pool does not survive `fork`, and inside a joblib/loky worker (Hydra's joblib
launcher) the global start method is `loky`, which spawned children cannot restore; both are
handled here.
"""

from __future__ import annotations

import multiprocessing
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing.context import SpawnContext

from tqdm import tqdm

STANDARD_METHODS = (None, "fork", "spawn", "forkserver")


def spawn_context() -> SpawnContext:
    """The `spawn` context, after making the global start method one a child can restore."""
    if multiprocessing.get_start_method(allow_none=True) not in STANDARD_METHODS:
        multiprocessing.set_start_method("spawn", force=True)
    return multiprocessing.get_context("spawn")


def process_pool(workers: int) -> ProcessPoolExecutor:
    """A pool of `workers` fresh interpreters."""
    return ProcessPoolExecutor(max_workers=max(workers, 1), mp_context=spawn_context())


def process_map(fn, jobs: list, workers: int, desc: str, progress: bool = True) -> list:
    """`fn` over `jobs` in a pool of fresh interpreters (results in job order), with a progress
    bar; in this process when one worker or one job is asked for."""
    if not jobs:
        return []
    if workers <= 1 or len(jobs) == 1:
        return [fn(j) for j in tqdm(jobs, desc=desc, disable=not progress)]
    out: list = [None] * len(jobs)
    with process_pool(min(workers, len(jobs))) as pool:
        futures = {pool.submit(fn, job): i for i, job in enumerate(jobs)}
        for future in tqdm(as_completed(futures), total=len(jobs), desc=desc, disable=not progress):
            out[futures[future]] = future.result()
    return out
