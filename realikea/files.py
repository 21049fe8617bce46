"""Where the project's files are and how it writes them (a reader never sees a half-written
file). The one module every layer may use for paths and writes.

Shipped with the package: its configs (`realikea/conf/`) and the catalog (`realikea/catalog/`).
Written by it: `outputs/`, `.cache/`, `experiments/` results and imported parts
(`assets/imported/`), all relative to the workspace: the source checkout the package runs from
(an editable install), else the current directory (an installed wheel)."""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent
CONF_DIR = PACKAGE_DIR / "conf"
CATALOG_DIR = PACKAGE_DIR / "catalog"


def _workspace() -> Path:
    checkout = PACKAGE_DIR.parent
    return checkout if (checkout / "pyproject.toml").is_file() else Path.cwd()


WORKSPACE = _workspace()


def repo_path(value: str | Path) -> Path:
    """A config path: absolute as given, relative to the workspace otherwise."""
    path = Path(value).expanduser()
    return path if path.is_absolute() else WORKSPACE / path


def shown_path(path: Path) -> str:
    """A path as a committed file names it: relative to the workspace when inside it."""
    return str(path.relative_to(WORKSPACE) if path.is_relative_to(WORKSPACE) else path)


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
