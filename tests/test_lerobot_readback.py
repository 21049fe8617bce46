"""The recorded LeRobot datasets read back by lerobot's own `LeRobotDataset` (lerobot 0.4.4),
compared with their files as pyarrow reads them: frames, episodes, features, the values of
frames, the tasks and the episodes' labels.

It runs in the read-back environment (experiments/lerobot_sample/make_env.sh: torch 2.14.1,
torchvision 0.29.1, lerobot 0.4.4), which has no realikea: this module imports none, and
experiments/lerobot_sample/readback.sh runs it with `--noconftest` on an export the project's
own Python has just written (REALIKEA_LEROBOT_EXPORT) and on the samples in
experiments/lerobot_sample/results/. Where lerobot is not installed (the project's environment,
CI) it skips, unless REALIKEA_LEROBOT_EXPORT is set: then a missing lerobot is an error."""

from __future__ import annotations

import json
import os
from importlib import metadata
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

if not os.environ.get("REALIKEA_LEROBOT_EXPORT"):
    pytest.importorskip("lerobot", reason="lerobot: experiments/lerobot_sample/readback.sh")

import torch  # noqa: E402  (after the skip: lerobot's own dependencies)
import torchvision  # noqa: E402
from lerobot.datasets.lerobot_dataset import LeRobotDataset  # noqa: E402

SAMPLES = Path(__file__).resolve().parents[1] / "experiments/lerobot_sample/results"
EXPORTS = [Path(p) for p in os.environ.get("REALIKEA_LEROBOT_EXPORT", "").split(os.pathsep) if p]
ROOTS = [*EXPORTS, *sorted(p.parent.parent for p in SAMPLES.glob("*/meta/info.json"))]
DTYPES = {"float32": torch.float32, "bool": torch.bool, "int64": torch.int64}


def files(root: Path) -> dict:
    """The dataset's files read by pyarrow alone."""
    return {
        "info": json.loads((root / "meta/info.json").read_text()),
        "tasks": pq.read_table(root / "meta/tasks.parquet").to_pylist(),
        "episodes": pq.read_table(root / "meta/episodes/chunk-000/file-000.parquet").to_pylist(),
        "data": pq.read_table(root / "data/chunk-000/file-000.parquet"),
    }


def test_the_real_lerobot_and_torchvision_are_loaded():
    """No stub: each module is its installed distribution's file, torchvision's compiled ops
    loaded (torchvision::nms runs)."""
    assert metadata.version("lerobot") == "0.4.4"
    import lerobot

    for module, name in ((lerobot, "lerobot"), (torchvision, "torchvision"), (torch, "torch")):
        installed = Path(metadata.distribution(name).locate_file(f"{name}/__init__.py"))
        assert Path(module.__file__).resolve() == installed.resolve(), name
    assert torchvision.extension._has_ops()
    boxes = torch.tensor([[0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, 0.9], [2.0, 2.0, 3.0, 3.0]])
    kept = torchvision.ops.nms(boxes, torch.tensor([0.9, 0.8, 0.7]), 0.5)
    assert kept.tolist() == [0, 2]


@pytest.fixture(scope="module", params=ROOTS, ids=lambda p: p.name)
def pair(request):
    """(the dataset as LeRobotDataset reads it, its files as pyarrow reads them)."""
    root = request.param
    return LeRobotDataset(f"realikea/{root.name}", root=root), files(root)


def test_frames_episodes_and_features(pair):
    ds, f = pair
    info, episodes = f["info"], f["episodes"]
    assert len(ds) == ds.num_frames == info["total_frames"] == f["data"].num_rows
    assert ds.num_episodes == info["total_episodes"] == len(episodes)
    assert ds.fps == info["fps"] == 10
    assert set(ds.features) == set(info["features"]) == set(f["data"].column_names)
    frame = ds[0]
    assert set(frame) == {*info["features"], "task"}
    for name, feature in info["features"].items():
        shape = () if feature["shape"] == [1] else tuple(feature["shape"])
        assert tuple(frame[name].shape) == shape, name
        assert frame[name].dtype == DTYPES[feature["dtype"]], name


def test_frames_hold_the_exported_values(pair):
    """The first, a middle and the last frame of every episode, feature by feature, exactly."""
    ds, f = pair
    tasks = {t["task_index"]: t["task"] for t in f["tasks"]}
    for e in f["episodes"]:
        start, end = e["dataset_from_index"], e["dataset_to_index"]
        assert end - start == e["length"]
        for i in (start, (start + end) // 2, end - 1):
            row = f["data"].slice(i, 1).to_pylist()[0]
            frame = ds[i]
            for name, value in row.items():
                assert frame[name].tolist() == value, (i, name)
            assert row["episode_index"] == e["episode_index"] and row["index"] == i
            assert frame["task"] == tasks[row["task_index"]] == e["tasks"][0]


def test_episodes_carry_their_labels(pair):
    ds, f = pair
    labels = ds.meta.episodes
    for key in ("episode_index", "length", "config_id", "outcome", "strategy", "failure_mode"):
        assert list(labels[key]) == [e[key] for e in f["episodes"]], key
    assert list(labels["tasks"]) == [e["tasks"] for e in f["episodes"]]


def test_windows_pad_past_an_episode_end(pair):
    ds, f = pair
    root = Path(ds.root)
    windows = LeRobotDataset(ds.repo_id, root=root, delta_timestamps={"action": [0, 0.1]})
    for e in f["episodes"]:
        last = windows[e["dataset_to_index"] - 1]
        assert last["action_is_pad"].tolist() == [False, True]
        assert torch.equal(last["action"][0], ds[e["dataset_to_index"] - 1]["action"])
        assert windows[e["dataset_from_index"]]["action_is_pad"].tolist() == [False, False]


def test_the_sample_readme_example():
    """experiments/lerobot_sample/README.md's lines, on the committed heuristic-pull sample."""
    ds = LeRobotDataset("realikea/heuristic_pull", root=SAMPLES / "heuristic_pull")
    forces = ds[138]["contact.forces"]  # episode 1, frame 60: friction on the knob
    assert np.allclose(forces.numpy(), [0.0, 20.7, 0.0, 0.0, 70.0], atol=0.05)
    assert (int(ds[138]["episode_index"]), int(ds[138]["frame_index"])) == (1, 60)
    assert list(ds.meta.episodes["failure_mode"]) == [None, None, None, "other"]
