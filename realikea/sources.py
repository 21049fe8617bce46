"""The collision sources a configuration is built with, and the files of its built model."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from realikea.errors import RealIkeaError

CollisionSource = Literal["coacd", "hull"]  # CoACD's convex pieces, or one sealed convex hull
SOURCES: tuple[CollisionSource, ...] = ("coacd", "hull")


def check_source(source: object) -> CollisionSource:
    """`source` if it is a collision source, else an error naming it and the choices."""
    if source not in SOURCES:
        raise RealIkeaError(f"unknown collision source {source!r}; choose {' or '.join(SOURCES)}")
    return source  # type: ignore[return-value]


def model_name(source: str, suffix: str = ".xml") -> str:
    """The file name of a configuration's model for `source`: model_<source>.xml (or the
    exported `.urdf` / `.usd`)."""
    return f"model_{source}{suffix}"


def model_path(library: Path, config_id: str, source: str) -> Path:
    """Where the library keeps one configuration's built MJCF: <library>/<id>/model_<source>.xml."""
    return Path(library) / config_id / model_name(source)


def built_model(library: Path, config_id: str, source: str) -> Path:
    """`model_path`, or an error saying the configuration is not built for `source`."""
    path = model_path(library, config_id, source)
    if not path.is_file():
        raise RealIkeaError(f"no {source} MJCF for {config_id} in {library}; build it first")
    return path
