"""A training run's metrics.csv (written by realikea/training/log_writer.py) as series per tag."""

from __future__ import annotations

import csv
from collections import defaultdict
from pathlib import Path


def read_metrics(run_dir: Path) -> dict[str, tuple[list[int], list[float]]]:
    """tag -> (iterations, values)."""
    series: dict[str, tuple[list[int], list[float]]] = defaultdict(lambda: ([], []))
    with (run_dir / "metrics.csv").open() as f:
        for row in csv.DictReader(f):
            its, values = series[row["tag"]]
            its.append(int(row["iteration"]))
            values.append(float(row["value"]))
    return series
