"""Content-addressed cache entries and atomic writes: a reader never sees a half-written file."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def atomic_path(path: Path):
    """Yield a temporary sibling of `path` (same suffix, so writers pick the same format) that
    replaces `path` only if the block succeeds; it is removed either way."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o644)  # mkstemp creates owner-only files
        os.replace(tmp, path)
    finally:
        Path(tmp).unlink(missing_ok=True)


def atomic_write_text(path: Path, text: str) -> None:
    """Write a text file via a temporary sibling and `os.replace`."""
    with atomic_path(path) as tmp:
        tmp.write_text(text)


@contextmanager
def staging_dir(final: Path):
    """Yield an empty temporary folder that replaces `final` only if the block succeeds."""
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=final.parent, prefix=f".{final.name}.", suffix=".tmp"))
    os.chmod(tmp, 0o755)  # mkdtemp creates owner-only folders
    try:
        yield tmp
        if final.exists():
            old = Path(tempfile.mkdtemp(dir=final.parent, prefix=f".{final.name}.", suffix=".old"))
            os.replace(final, old / final.name)
            os.replace(tmp, final)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, final)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


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
