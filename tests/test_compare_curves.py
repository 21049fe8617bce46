"""experiments/tools/compare_curves.py: several runs' training success on one axis (the script
run as a user runs it; its running mean from the package)."""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from realikea.files import WORKSPACE
from realikea.training.metrics import running_mean

SCRIPT = WORKSPACE / "experiments" / "tools" / "compare_curves.py"


def _run(folder, successes):
    folder.mkdir()
    rows = ["iteration,tag,value"]
    rows += [f"{i},/episode/success,{v}" for i, v in enumerate(successes)]
    rows += [f"{i},Train/mean_reward/time,{10 * i}" for i in range(len(successes))]
    (folder / "metrics.csv").write_text("\n".join(rows) + "\n")
    return folder


def test_the_running_mean_averages_the_window_and_fewer_at_the_start():
    np.testing.assert_allclose(running_mean([1, 0, 1, 0], window=2), [1, 0.5, 0.5, 0.5])
    np.testing.assert_allclose(running_mean([0.2] * 60, window=50), [0.2] * 60)


def _curves(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True)


def test_a_label_may_hold_equals_signs_and_a_folder_without_metrics_is_refused(tmp_path):
    run = _run(tmp_path / "a", [0.0, 1.0])
    out = tmp_path / "curves.png"
    assert _curves("--out", str(out), f"w_open2 = 2={run}").returncode == 0 and out.is_file()
    for bad in (str(run), f"empty={tmp_path}"):
        done = _curves("--out", str(tmp_path / "bad.png"), bad)
        assert done.returncode == 2 and "expected LABEL=RUN_DIR" in done.stderr


def test_two_runs_make_one_png_and_a_bad_run_writes_nothing(tmp_path):
    a, b = _run(tmp_path / "a", [0.0, 0.5, 1.0]), _run(tmp_path / "b", [0.0, 0.0, 0.1])
    out = tmp_path / "plots" / "curves.png"
    cmd = [sys.executable, str(SCRIPT), "--out", str(out), "--switch", "1", f"A={a}", f"B={b}"]
    assert subprocess.run(cmd, capture_output=True, text=True).returncode == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    bad = tmp_path / "bad.png"
    done = subprocess.run(
        [sys.executable, str(SCRIPT), "--out", str(bad), f"A={a}", f"B={tmp_path}"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2 and "expected LABEL=RUN_DIR" in done.stderr
    assert not bad.exists()
