"""A training run's metrics.csv (written by realikea/training/log_writer.py) as series per tag,
the rows of several launches of one run joined, a running mean for curves, a tag's mean over each
full window, and each category x kind group's training success over the run's last full window."""

from __future__ import annotations

import csv
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

from realikea.assets.catalog import GROUPS

WINDOW = 25  # iterations of the last full window a group's training success is read over


def read_metrics(run_dir: Path) -> dict[str, tuple[list[int], list[float]]]:
    """tag -> (iterations, values), a resumed run's launches joined (`join_launches`)."""
    series: dict[str, tuple[list[int], list[float]]] = defaultdict(lambda: ([], []))
    with (run_dir / "metrics.csv").open() as f:
        for row in csv.DictReader(join_launches(f.read().splitlines())):
            its, values = series[row["tag"]]
            its.append(int(row["iteration"]))
            values.append(float(row["value"]))
    return series


def join_launches(lines: list[str]) -> list[str]:
    """metrics.csv lines (header first) of several launches of one run, each iteration as the
    last launch that logged it wrote it: a run resumed from a checkpoint repeats that iteration
    (and those after it, from an earlier checkpoint than its last), and its rows replace the
    earlier launch's from there on. A launch starts where an iteration goes back or a row of
    the current launch repeats; rsl-rl's `.../time` tags count seconds from each launch, not
    iterations, so they all stay."""
    header, rows = lines[0], lines[1:]
    launches: list[list[str]] = [[]]
    seen: set[tuple[str, str]] = set()
    previous = -1
    for row in rows:
        iteration, tag = row.split(",")[:2]
        if not tag.endswith("/time"):
            if int(iteration) < previous or (iteration, tag) in seen:
                launches.append([])
                seen = set()
            previous = int(iteration)
            seen.add((iteration, tag))
        launches[-1].append(row)
    kept: list[str] = []
    resumed_at = math.inf  # the first iteration of the launches after this one
    for launch in reversed(launches):
        cells = [row.split(",")[:2] for row in launch]
        kept = [
            row for row, (iteration, tag) in zip(launch, cells, strict=True)
            if tag.endswith("/time") or int(iteration) < resumed_at
        ] + kept  # fmt: skip
        logged = [int(iteration) for iteration, tag in cells if not tag.endswith("/time")]
        resumed_at = min([resumed_at, *logged])
    return [header, *kept]


def running_mean(values: list[float], window: int) -> np.ndarray:
    """The mean of each value and the window - 1 before it (fewer at the start)."""
    cumulative = np.concatenate([[0.0], np.cumsum(values)])
    ends = np.arange(1, len(values) + 1)
    starts = np.maximum(ends - window, 0)
    return (cumulative[ends] - cumulative[starts]) / (ends - starts)


def logged_iterations(metrics: dict[str, tuple[list[int], list[float]]]) -> int:
    """How many iterations a run logged (its last iteration + 1; 0: none); rsl-rl's `.../time`
    tags are stepped in seconds, every other tag in iterations."""
    logged = [max(its) for tag, (its, _) in metrics.items() if its and not tag.endswith("/time")]
    return max(logged) + 1 if logged else 0


def window_means(
    its: list[int], values: list[float], iterations: int, window: int = WINDOW
) -> list[float | None]:
    """A tag's mean over each full window of a run that logged `iterations` (iterations
    k * window .. (k + 1) * window - 1, for every k whose window ends by then): the mean of the
    iterations in it that logged the tag (a group is logged only where one of its episodes
    finished), None where none did. A partial last window is left out."""
    at, of = np.asarray(its, dtype=int), np.asarray(values, dtype=float)
    means: list[float | None] = []
    for start in range(0, iterations - window + 1, window):
        chosen = of[(at >= start) & (at < start + window)]
        means.append(float(chosen.mean()) if chosen.size else None)
    return means


def success_tag(group: str, pad_enters: bool = False) -> str:
    """The metric a group is read on: its training success, or (`pad_enters`, finger-pull
    groups) its success on parts whose channel the fingertip pad enters."""
    if pad_enters and group.startswith("finger_pull_"):
        return f"/pad_enters_success/{group}"
    return f"/success/{group}"


def last_window(run: Path, pad_enters: bool = False) -> dict[str, float | None]:
    """Each group's mean training success over the run's last full WINDOW iterations
    (iterations N - WINDOW .. N - 1 of a run that logged N; None: no entry there, or the run
    is shorter than the window); `pad_enters`: see `success_tag`."""
    metrics = read_metrics(run)
    last = logged_iterations(metrics) - 1
    out: dict[str, float | None] = {}
    for group in GROUPS:
        its, values = (np.asarray(x) for x in metrics.get(success_tag(group, pad_enters), ([], [])))
        chosen = values[its >= last - WINDOW + 1] if last + 1 >= WINDOW else values[:0]
        out[group] = float(chosen.mean()) if chosen.size else None
    return out
