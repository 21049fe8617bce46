"""experiments/tools/windows.py: a run's tags as full-window means (the package's window_means,
and the script run as a user runs it)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from realikea.files import WORKSPACE
from realikea.training.metrics import logged_iterations, read_metrics, window_means

SCRIPT = WORKSPACE / "experiments" / "tools" / "windows.py"


def _run(folder, iterations):
    """A run that logged `iterations`: a loss every iteration, a group's success only on odd
    iterations below 50 (sparse, then absent), and a seconds-stepped time tag past the end."""
    folder.mkdir()
    rows = ["iteration,tag,value"]  # each iteration's rows together, as the run writes them
    for i in range(iterations):
        rows.append(f"{i},Loss/behavior,{i}")
        if i % 2 and i < 50:
            rows.append(f"{i},/success/knob_door,{i % 4 // 2}")
    rows.append(f"{10 * iterations},Train/mean_reward/time,1.0")
    (folder / "metrics.csv").write_text("\n".join(rows) + "\n")
    return folder


def test_windows_are_full_sparse_entries_averaged_and_empty_ones_none(tmp_path):
    metrics = read_metrics(_run(tmp_path / "run", 80))
    assert logged_iterations(metrics) == 80  # the time tag's seconds do not count
    assert window_means(*metrics["Loss/behavior"], 80) == [12.0, 37.0, 62.0]  # 75-79 left out
    # odd iterations 1, 3, ..., 23 alternate 0, 1: half; 25 .. 49 likewise; none after 50
    assert window_means(*metrics["/success/knob_door"], 80) == [0.5, pytest.approx(6 / 13), None]
    assert window_means(*metrics["Loss/behavior"], 80, window=40) == [19.5, 59.5]
    assert window_means(*metrics["Loss/behavior"], 24) == []
    assert logged_iterations({}) == 0


def _windows(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True)


def test_the_script_prints_one_row_a_window(tmp_path):
    run = _run(tmp_path / "run", 75)
    done = _windows(str(run), "/success/knob_door", "Loss/behavior")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert "75 iterations, 3 full windows of 25" in lines[0]
    assert lines[3:] == [
        "| 0–24 | 0.500 | 12.000 |",
        "| 25–49 | 0.462 | 37.000 |",
        "| 50–74 | – | 62.000 |",
    ]


def test_bad_input_is_refused_naming_it(tmp_path):
    run = _run(tmp_path / "run", 30)
    unknown = _windows(str(run), "Loss/behavior", "/success/nope")
    assert unknown.returncode == 2 and "never logged /success/nope" in unknown.stderr
    assert unknown.stdout == ""
    bare = _windows(str(tmp_path), "Loss/behavior")
    assert bare.returncode == 2 and f"no metrics.csv in {tmp_path}" in bare.stderr
    zero = _windows(str(run), "Loss/behavior", "--window", "0")
    assert zero.returncode == 2 and "--window 0" in zero.stderr
