"""Content-addressed cache entries: built once in a temporary folder, renamed into place."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path


def cached_entry(root: Path, key: str, build: Callable[[Path], None]) -> tuple[Path, bool]:
    """Return (`root/key`, built) building the entry with `build(folder)` on a miss.

    Entries are content-addressed, so when two processes race the first rename wins and the
    loser's identical copy is discarded.
    """
    entry = root / key
    if entry.is_dir():
        return entry, False
    root.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=root, prefix=f".{key}.", suffix=".tmp"))
    os.chmod(tmp, 0o755)
    try:
        build(tmp)
        try:
            os.rename(tmp, entry)
        except OSError:
            if not entry.is_dir():
                raise
            return entry, False
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return entry, True


def link_or_copy(src: Path, dst: Path) -> None:
    """Hard-link a cached file into an output folder, copying across file systems."""
    dst.parent.mkdir(parents=True, exist_ok=True)
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)
