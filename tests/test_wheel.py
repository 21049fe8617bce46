"""The package is self-contained: built as a wheel and installed (not editable) into a fresh
environment, it finds its configs and catalog and runs a command from any directory, writing its
outputs there."""

from __future__ import annotations

import shutil
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path

from realikea.files import WORKSPACE


def test_an_installed_wheel_builds_a_configuration_from_any_directory(tmp_path):
    source, wheels = tmp_path / "source", tmp_path / "wheels"  # built off the checkout
    shutil.copytree(WORKSPACE / "realikea", source / "realikea",
                    ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(WORKSPACE / name, source / name)
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation",
         "-w", str(wheels), str(source)],
        check=True, capture_output=True,
    )  # fmt: skip
    (wheel,) = wheels.glob("realikea-*.whl")
    env = tmp_path / "env"
    venv.EnvBuilder(with_pip=False).create(env)
    python = env / "bin" / "python"
    # the dependencies come from this interpreter's environment, named in a path file:
    # `system_site_packages` would give the base interpreter's, which inside a venv (setup.sh's
    # .venv on an externally managed Python) is not where they are installed
    env_site = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
        check=True, capture_output=True, text=True,
    ).stdout.strip()  # fmt: skip
    ours = dict.fromkeys(sysconfig.get_path(k) for k in ("purelib", "platlib"))
    (Path(env_site) / "dependencies.pth").write_text("\n".join(ours) + "\n")
    subprocess.run(
        [sys.executable, "-m", "pip", "--python", str(python), "install", "-q", "--no-deps",
         str(wheel)],
        check=True, capture_output=True,
    )  # fmt: skip
    work = tmp_path / "work"
    work.mkdir()
    where = subprocess.run(
        [python, "-c", "import realikea; print(realikea.__file__)"],
        cwd=work, check=True, capture_output=True, text=True,
    ).stdout  # fmt: skip
    assert str(env) in where  # the installed copy, not this checkout
    # a concavity threshold this loose ends CoACD (run for every part, cached beside the hull)
    # at its first piece: the build is about finding configs and catalog, not mesh quality
    out = subprocess.run(
        [env / "bin" / "realikea", "assets", "build", "--part", "knob_round_30", "--base",
         "drawer_w60_h20", "--collision", "hull", "--workers", "1",
         "workflow.coacd.threshold=0.5"],
        cwd=work, capture_output=True, text=True,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr[-2000:]
    assert (
        work / "outputs" / "assets" / "knob_round_30__drawer_w60_h20" / "model_hull.xml"
    ).is_file()
