"""Training curves of a run: trailing means, the first full window at a success level, and
the plateau check over the last windows."""

from __future__ import annotations

import numpy as np

SUCCESS_WINDOW = 20  # iterations averaged for "training success reached 50 %" and the curves
# iterations per window of the plateau check (training success over the last window against
# the one before): a grid run should train until its success has plateaued
PLATEAU_WINDOW = 100


def iterations_to_success(
    run: dict, level: float = 0.5, window: int = SUCCESS_WINDOW
) -> int | None:
    """The first iteration from which the training success, averaged over the next `window`
    iterations, reaches `level` (None if it never does). A window counts only when it is full,
    ending at or before the run's last iteration: the mean of a run's last few iterations, a
    window cut off by the end of training, never counts as learned."""
    its, values = (np.asarray(x) for x in run["metrics"].get("/episode/success", ([], [])))
    for start in np.unique(its):
        if start + window - 1 > its.max():  # the window runs past the last iteration
            break
        chosen = (its >= start) & (its < start + window)
        if values[chosen].mean() >= level:
            return int(start)
    return None


def last_windows(
    run: dict, tag: str, window: int = PLATEAU_WINDOW
) -> tuple[float | None, float | None]:
    """The mean of a training metric over the last `window` iterations and its change from the
    `window` before them (None where a window has no iteration): a plateau changes little."""
    its, values = (np.asarray(x) for x in run["metrics"].get(tag, ([], [])))
    if its.size == 0:
        return None, None
    end = its.max() + 1
    last = values[its >= end - window]
    before = values[(its >= end - 2 * window) & (its < end - window)]
    mean = float(last.mean())
    return mean, (mean - float(before.mean())) if before.size else None


def trailing_mean(its, values, window: int) -> tuple[np.ndarray, np.ndarray]:
    """The mean of `values` over each `window` consecutive iterations, at the window's last
    iteration (nothing before a full window)."""
    its, values = np.asarray(its), np.asarray(values, float)
    if len(values) < window:
        return its[:0], values[:0]
    order = np.argsort(its, kind="stable")
    its, values = its[order], values[order]
    # summed, then divided: a window of exactly half successes averages 0.5, as in
    # iterations_to_success, not a rounding error below it
    means = np.convolve(values, np.ones(window), mode="valid") / window
    return its[window - 1 :], means
