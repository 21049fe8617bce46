"""The pool's shared-memory block: per env its action, observation, last observation of an ended
episode, reward and end flags; per worker its fault counters. One block, 64-byte aligned arrays,
written by the worker that owns an env and read by the pool after each command."""

from __future__ import annotations

import numpy as np

COUNTERS = ("divergence_resets", "bad_action_resets")  # counted where the envs are stepped


def fields(num_envs: int, num_workers: int, obs_size: int, action_size: int):
    """(name, shape, dtype) of every shared array."""
    n, w = num_envs, max(num_workers, 1)
    return (
        ("action", (n, action_size), np.float64),
        ("obs", (n, obs_size), np.float64),
        ("final_obs", (n, obs_size), np.float64),
        ("reward", (n,), np.float64),
        ("terminated", (n,), np.bool_),
        ("truncated", (n,), np.bool_),
        ("counters", (w, len(COUNTERS)), np.int64),
    )


def layout(*sizes) -> tuple[dict[str, tuple[int, tuple, type]], int]:
    """Byte offset, shape and dtype of every array of `fields(*sizes)`, and the block's size."""
    out, offset = {}, 0
    for name, shape, dtype in fields(*sizes):
        out[name] = (offset, shape, dtype)
        nbytes = int(np.prod(shape)) * np.dtype(dtype).itemsize
        offset += -(-nbytes // 64) * 64
    return out, max(offset, 64)


def views(buffer, *sizes) -> dict[str, np.ndarray]:
    """numpy arrays over `buffer` (a bytearray in-process, a RawArray shared with workers)."""
    arrays, _ = layout(*sizes)
    return {
        name: np.frombuffer(buffer, dtype=dtype, count=int(np.prod(shape)), offset=off).reshape(
            shape
        )
        for name, (off, shape, dtype) in arrays.items()
    }
