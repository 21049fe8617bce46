"""The one way this project starts worker processes: fresh interpreters (`spawn`).

CoACD's OpenMP pool does not survive `fork`, and inside a joblib/loky worker (Hydra's joblib
launcher) the global start method is `loky`, which spawned children cannot restore; both are
handled here.
"""

from __future__ import annotations

import multiprocessing
from multiprocessing.context import SpawnContext

STANDARD_METHODS = (None, "fork", "spawn", "forkserver")


def spawn_context() -> SpawnContext:
    """The `spawn` context, after making the global start method one a child can restore."""
    if multiprocessing.get_start_method(allow_none=True) not in STANDARD_METHODS:
        multiprocessing.set_start_method("spawn", force=True)
    return multiprocessing.get_context("spawn")
