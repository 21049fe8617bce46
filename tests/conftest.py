"""Shared fixtures: the catalog, default workflow settings, a small built library, its export
sample and their release, the experiments' scripts as modules, the config train.py composes,
and the training log of hand-made episodes."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys

import pytest

from realikea.assets.build import WorkflowSettings, build_library
from realikea.assets.catalog import CATEGORIES, Catalog
from realikea.config import load_config
from realikea.eval.library_grid import KINDS
from realikea.export.release import release_library
from realikea.files import WORKSPACE, repo_path
from realikea.sources import SOURCES

SAMPLE_BASES = ("drawer_w60_h20", "door_left_w40_h80", "door_right_w60_h80", "flap_w60_h40")


@pytest.fixture
def write_cells():
    """`write_cells(folder, modes, success=0.9, low=None)`: an evaluated run's cells.jsonl, 50
    episodes a cell, every group at `success` in each mode but `low` = (kind, category, mode,
    value)."""

    def write(folder, modes, success=0.9, low=None):
        folder.mkdir(parents=True, exist_ok=True)
        lines = []
        for kind in KINDS:
            for category in CATEGORIES:
                for mode in modes:
                    value = low[3] if low and (kind, category, mode) == low[:3] else success
                    record = {"kind": kind, "category": category, "resistance": mode,
                              "episodes": 50, "success": value}  # fmt: skip
                    lines.append(json.dumps(record))
        (folder / "cells.jsonl").write_text("\n".join(lines) + "\n")

    return write


@pytest.fixture(scope="session")
def episode_log():
    """`episode_log(episodes)`: what the rsl-rl env logs for these finished episodes' records
    (`RslRlVecEnv._log`, over a stand-in pool)."""
    from types import SimpleNamespace

    from realikea.pool.rsl_rl_env import RslRlVecEnv

    pool = SimpleNamespace(num_envs=3, num_actions=5, obs_size=4, horizon=10, iteration=0)
    pool.counters = {}
    return RslRlVecEnv(pool, load_config(), 8)._log


@pytest.fixture(scope="session")
def load_script():
    """`load_script("experiments/x/y.py")`: an experiment's script imported as a module (the
    experiments folder is no package), its folder on sys.path while it loads, as when run, so
    it can import its sibling scripts. A module of a study's package
    (`experiments/x/pkg/z.py`, beside an `__init__.py`) is imported as `pkg.z`, as its
    scripts import it."""

    def load(relative: str):
        path = WORKSPACE / relative
        if (path.parent / "__init__.py").is_file():
            sys.path.insert(0, str(path.parent.parent))
            try:
                return importlib.import_module(f"{path.parent.name}.{path.stem}")
            finally:
                sys.path.remove(str(path.parent.parent))
        spec = importlib.util.spec_from_file_location(path.stem, path)
        module = importlib.util.module_from_spec(spec)
        sys.modules[path.stem] = module  # where dataclasses look their module up
        sys.path.insert(0, str(path.parent))
        try:
            spec.loader.exec_module(module)
        finally:
            sys.path.remove(str(path.parent))
        return module

    return load


@pytest.fixture(scope="session")
def catalog() -> Catalog:
    return Catalog.load()


@pytest.fixture(scope="session")
def settings() -> WorkflowSettings:
    return WorkflowSettings.from_config(load_config())


@pytest.fixture(scope="session")
def cache_root():
    """The project's own content-addressed cache: shared with users, safe by construction."""
    return repo_path(load_config().paths.cache)


@pytest.fixture(scope="session")
def sample_configs(catalog):
    """The first part of each category on a drawer, both doors and the flap."""
    parts = [catalog.parts_in(c)[0] for c in CATEGORIES]
    return [
        c for p in parts for b in SAMPLE_BASES for c in catalog.configurations(part=p.id, base=b)
    ]


def build_sample(configs, settings, cache_root, out):
    """Build configurations for both collision sources (at the nominal resistance), quietly."""
    return build_library(configs, settings, SOURCES, cache_root, out, progress=False)


@pytest.fixture(scope="session")
def sample_library(tmp_path_factory, sample_configs, settings, cache_root):
    """The sample built for both collision sources."""
    out = tmp_path_factory.mktemp("library")
    return out, build_sample(sample_configs, settings, cache_root, out)


# the smallest training run: one bar on one drawer, fixed pose, two envs stepped in-process,
# 1.5 s episodes
SMALL_RUN = [
    "asset=two_point",
    "asset.part=tp_round_bar_128",
    "asset.base=drawer_w60_h20",
    "dr=fixed",
    "env.num_envs=2",
    "env.num_workers=0",
    "task.episode_seconds=1.5",
]

# what the export, release and verify tests export: a bar on a drawer (a gap behind it), a cup
# pull on the flap (a channel behind its lip) and a knob on a door (no gap)
EXPORT_SAMPLE = {
    "drawer": ("tp_round_bar_128", "drawer_w60_h20"),
    "flap": ("fp_cup_128", "flap_w60_h40"),
    "door": ("knob_round_30", "door_left_w40_h80"),
}


@pytest.fixture(scope="session")
def export_library(tmp_path_factory, catalog, settings, cache_root):
    """EXPORT_SAMPLE built once for both collision sources."""
    out = tmp_path_factory.mktemp("export_library")
    configs = [next(catalog.configurations(part=p, base=b)) for p, b in EXPORT_SAMPLE.values()]
    build_sample(configs, settings, cache_root, out)
    return out


@pytest.fixture(scope="session")
def export_configs(catalog):
    """EXPORT_SAMPLE's drawer with a bar and door with a knob (built in `export_library`)."""
    return [
        next(catalog.configurations(part=p, base=b))
        for p, b in (EXPORT_SAMPLE["drawer"], EXPORT_SAMPLE["door"])
    ]


@pytest.fixture(scope="session")
def export_release(tmp_path_factory, export_configs, export_library):
    """`export_configs` released in every format and source, with its report: built once for
    test_release and test_verify, whose tests read it or copy it before changing it."""
    out = tmp_path_factory.mktemp("release") / "release"
    return out, release_library(export_configs, export_library, out, progress=False)


# what `train.py --cfg job` composes in test_config and test_train_eval
TRAIN_PY_JOB = ["--cfg", "job", "asset=knob", "collision=hull", "resistance=high"]


@pytest.fixture(scope="session")
def train_py_job() -> str:
    """The job config `train.py TRAIN_PY_JOB` prints, composed once: each launch starts a Python
    with train.py's imports (20-30 s on a loaded machine) for a config that does not change."""
    out = subprocess.run(
        [sys.executable, "train.py", *TRAIN_PY_JOB], cwd=WORKSPACE, capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout
