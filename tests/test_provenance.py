"""The versions recorded beside a result: installed packages named, missing ones None."""

from __future__ import annotations

import platform

import mujoco

from realikea.provenance import RESULT_PACKAGES, package_versions, result_versions


def test_installed_packages_give_their_version_and_missing_ones_none():
    versions = package_versions(("mujoco", "no-such-package-realikea"))
    assert versions == {"mujoco": mujoco.__version__, "no-such-package-realikea": None}


def test_result_versions_name_python_and_every_result_package():
    versions = result_versions()
    assert versions["python"] == platform.python_version()
    assert set(versions) == {"python", *RESULT_PACKAGES}
