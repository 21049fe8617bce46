"""The installed versions of the packages that decide a result, recorded beside it.

MuJoCo 4.0.0 (2026-11-06) moved a recorded episode's rewards by 1e-12 relative
(tests/test_reward_replay.py): numbers made under different engines are not bit-comparable, so
every evaluation names the engine, learner and array library it ran on.
"""

from __future__ import annotations

import platform
from importlib import metadata

RESULT_PACKAGES = ("mujoco", "torch", "numpy", "rsl-rl-lib", "mink")  # what an eval.json names


def package_versions(names: tuple[str, ...]) -> dict[str, str | None]:
    """Each package's installed version, None when it is not installed."""
    versions = {}
    for name in names:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = None
    return versions


def result_versions() -> dict[str, str | None]:
    """Python's version and RESULT_PACKAGES' versions: what an evaluation records."""
    return {"python": platform.python_version(), **package_versions(RESULT_PACKAGES)}
