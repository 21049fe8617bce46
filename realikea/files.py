"""Where the repository's files are and how the project writes them: a reader never sees a
half-written file. The one module every layer may use for paths and writes."""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]


def repo_path(value: str | Path) -> Path:
    """A config path: absolute as given, relative to the repository root otherwise."""
    path = Path(value).expanduser()
    return path if path.is_absolute() else REPO_ROOT / path


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
