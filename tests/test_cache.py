"""Cache entries and writes are atomic: an interrupted build leaves nothing behind."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from realikea.assets.cache import cached_entry
from realikea.files import atomic_write_text, staging_dir


def test_cached_entry_builds_once(tmp_path):
    calls = []

    def build(folder):
        calls.append(folder)
        (folder / "mesh.obj").write_text("v 0 0 0\n")

    first, built_first = cached_entry(tmp_path, "abc", build)
    second, built_second = cached_entry(tmp_path, "abc", build)
    assert (built_first, built_second) == (True, False)
    assert first == second == tmp_path / "abc"
    assert len(calls) == 1 and (first / "mesh.obj").read_text() == "v 0 0 0\n"


def test_failed_build_leaves_no_entry(tmp_path):
    def build(folder):
        (folder / "half.obj").write_text("v 0 0")
        raise KeyboardInterrupt  # the user pressed Ctrl-C mid-write

    with pytest.raises(KeyboardInterrupt):
        cached_entry(tmp_path, "abc", build)
    assert list(tmp_path.iterdir()) == []


def test_staging_replaces_existing_folder_only_on_success(tmp_path):
    final = tmp_path / "config"
    with staging_dir(final) as tmp:
        (tmp / "model.xml").write_text("old")
    with pytest.raises(RuntimeError), staging_dir(final) as tmp:
        (tmp / "model.xml").write_text("new, half")
        raise RuntimeError("assembly failed")
    assert (final / "model.xml").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["config"]


def test_atomic_write_text_keeps_old_content_on_failure(tmp_path, monkeypatch):
    path = tmp_path / "index.csv"
    atomic_write_text(path, "old\n")

    def fail(*args):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", fail)
    with pytest.raises(OSError):
        atomic_write_text(path, "new\n")
    assert path.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["index.csv"]


def test_killed_process_leaves_no_cache_entry(tmp_path):
    """SIGKILL in the middle of a build: the entry is absent, only a hidden temporary remains."""
    script = (
        "import sys, time\n"
        "from pathlib import Path\n"
        "from realikea.assets.cache import cached_entry\n"
        "def build(folder):\n"
        "    (folder / 'visual.obj').write_text('v 0 0 0')\n"
        "    print('writing', flush=True)\n"
        "    time.sleep(30)\n"
        "cached_entry(Path(sys.argv[1]), 'key', build)\n"
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", script, str(tmp_path)], stdout=subprocess.PIPE, text=True
    )
    assert proc.stdout.readline().strip() == "writing"
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=10)
    time.sleep(0.1)
    assert not (tmp_path / "key").exists()
    assert all(p.name.startswith(".") for p in tmp_path.iterdir())
