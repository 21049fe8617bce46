"""`realikea eval ... record=DIR` and teleop demonstrations as LeRobotDataset v3.0, read back per
the layout (lerobot 0.4's, realikea/datasets/lerobot.py). lerobot itself reads them back in an
environment of its own: tests/test_lerobot_readback.py, experiments/lerobot_sample/readback.sh."""

from __future__ import annotations

import contextlib
import io
import json
import re
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from realikea.assets.catalog import CATEGORIES
from realikea.assets.library import training_configurations
from realikea.cli import main
from realikea.config import load_config
from realikea.datasets import lerobot
from realikea.errors import RealIkeaError
from realikea.eval.record import PART_WORDS, features, record_demonstration
from realikea.policies.demonstration import Recorder, Session
from realikea.policies.heuristic_pull import HeuristicPull
from realikea.tasks import observations
from realikea.tasks.contacts import SAMPLE_FORCES
from realikea.tasks.open_task import OpenTask

PIN = ["asset=two_point", "asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20"]
# two 10 s episodes of the heuristic pull on one configuration: it pinches the bar open
EVAL = ["policy=heuristic_pull", *PIN, "asset.split=train", "dr=fixed", "episodes=2"]
EVAL += ["env.num_workers=0", "task.episode_seconds=10"]
CONFIG_ID = "tp_round_bar_128__drawer_w60_h20"
TASK = "open the drawer by its two-point handle"


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """An asset library of its own: the pinned configuration is built into it."""
    return tmp_path_factory.mktemp("library")


@pytest.fixture(scope="module")
def recorded(library, tmp_path_factory):
    """(dataset folder, the eval's JSON line) of a recorded eval."""
    root = tmp_path_factory.mktemp("record") / "pull"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["eval", *EVAL, f"paths.library={library}", f"record={root}"]) == 0
    lines = out.getvalue().strip().splitlines()
    assert f"LeRobot dataset: {root}" in lines
    return root, json.loads(lines[-1])


def read(root: Path) -> dict:
    """The dataset's files as the v3.0 layout names them."""
    meta = root / "meta"
    return {
        "info": json.loads((meta / "info.json").read_text()),
        "stats": json.loads((meta / "stats.json").read_text()),
        "tasks": pq.read_table(meta / "tasks.parquet"),
        "episodes": pq.read_table(meta / "episodes/chunk-000/file-000.parquet").to_pylist(),
        "data": pq.read_table(root / "data/chunk-000/file-000.parquet"),
    }


def column(data, name: str) -> np.ndarray:
    """A data column as (frames,) or (frames, size)."""
    values = data.column(name).combine_chunks()
    if hasattr(values, "flatten"):
        return values.flatten().to_numpy().reshape(len(values), -1)
    return values.to_numpy(zero_copy_only=False)


def test_frames_and_features_follow_the_v3_layout(recorded):
    root, summary = recorded
    ds = read(root)
    info, data, episodes = ds["info"], ds["data"], ds["episodes"]
    assert info["codebase_version"] == "v3.0" and info["fps"] == 10
    assert info["data_path"] == "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
    assert info["video_path"] is None and info["robot_type"] == "panda"
    assert info["total_episodes"] == summary["episodes"] == len(episodes) == 2
    lengths = [e["length"] for e in episodes]
    assert lengths == [e["episode_steps"] for e in episodes] == [100, 100]
    assert info["total_frames"] == data.num_rows == sum(lengths)
    assert info["splits"] == {"train": "0:2"} and info["total_tasks"] == 1
    shapes = {name: ft["shape"] for name, ft in info["features"].items()}
    assert shapes == {
        "observation.state": [observations.SIZE], "action": [5], "next.reward": [1],
        "next.done": [1], "next.opening": [1], "contact.forces": [len(SAMPLE_FORCES)],
        "timestamp": [1], "frame_index": [1], "episode_index": [1], "index": [1],
        "task_index": [1],
    }  # fmt: skip
    assert info["features"]["contact.forces"]["names"] == list(SAMPLE_FORCES)
    assert len(info["features"]["observation.state"]["names"]) == observations.SIZE
    assert set(data.column_names) == set(shapes)
    for name, shape in shapes.items():
        assert column(data, name).shape[1:] == (() if shape == [1] else tuple(shape)), name
    assert np.array_equal(column(data, "index"), np.arange(data.num_rows))
    for k, e in enumerate(episodes):
        rows = slice(e["dataset_from_index"], e["dataset_to_index"])
        assert (column(data, "episode_index")[rows] == k).all()
        assert np.array_equal(column(data, "frame_index")[rows], np.arange(e["length"]))
        assert column(data, "timestamp")[rows][-1] == pytest.approx((e["length"] - 1) / 10)
        assert e["data/chunk_index"] == e["data/file_index"] == 0
        assert e["stats/action/count"] == [e["length"]]
    assert ds["stats"]["observation.state"]["count"] == [data.num_rows]
    assert len(ds["stats"]["action"]["q50"]) == 5
    tasks = ds["tasks"]  # a pandas frame indexed by the task, as lerobot reads it
    assert tasks.to_pydict() == {"task": [TASK], "task_index": [0]}
    assert tasks.schema.pandas_metadata["index_columns"] == ["task"]
    assert not list(root.parent.glob(".*"))  # the staging folder is gone


def test_episodes_carry_configuration_and_labels(recorded):
    root, summary = recorded
    for e in read(root)["episodes"]:
        assert e["config_id"] == CONFIG_ID and e["part"] == "tp_round_bar_128"
        assert e["base"] == "drawer_w60_h20" and e["category"] == "two_point"
        assert e["kind"] == "drawer" and e["collision"] == "coacd"
        assert e["policy"] == "heuristic_pull" and e["resistance"] == "normal"
        assert e["tasks"] == [TASK]
        assert e["outcome"] == "success" and e["strategy"] == "pinch"
        assert e["failure_mode"] is None  # a success has none
        assert e["friction_share"] > 0.9 and e["termination"] == "timeout"
    assert summary["success"] == 1.0 and summary["strategies"]["pinch"] == 1.0


def test_steps_agree_with_their_episode(recorded):
    root, _ = recorded
    ds = read(root)
    data = ds["data"]
    opening_term = observations.slices()["opening"].start
    state, opening = column(data, "observation.state"), column(data, "next.opening")
    forces, done = column(data, "contact.forces"), column(data, "next.done")
    for e in ds["episodes"]:
        rows = slice(e["dataset_from_index"], e["dataset_to_index"])
        # the opening after step t is the observation of step t + 1
        assert np.array_equal(state[rows][1:, opening_term], opening[rows][:-1])
        assert opening[rows][-1] == pytest.approx(e["opening"], rel=1e-6)
        assert done[rows].tolist() == [False] * (e["length"] - 1) + [True]
        reward = column(data, "next.reward")[rows]
        assert reward.sum() == pytest.approx(e["episode_return"], rel=1e-5)
        part = dict(zip(SAMPLE_FORCES, forces[rows].T, strict=True))
        assert part["part_friction"].sum() > 5 * abs(part["part_normal"].sum())  # a pinch
        assert part["grip"].max() > 50  # the hand's 70 N squeeze
        assert (part["grip"][:5] == 0).all()  # no contact at the start


@pytest.mark.parametrize("existing", ["file", "folder"])
def test_a_bad_target_is_refused_before_any_episode(library, tmp_path, capsys, existing):
    target = tmp_path / "taken"
    if existing == "file":
        target.write_text("keep me")
    else:
        target.mkdir()
        (target / "notes.txt").write_text("keep me")
    before = sorted(p.name for p in tmp_path.iterdir())
    argv = ["eval", *EVAL, "episodes=1", f"paths.library={library}", f"record={target}"]
    assert main(argv) == 2
    err = capsys.readouterr()
    assert str(target) in err.err
    assert ("is a file" if existing == "file" else "is not empty") in err.err
    assert "episodes" not in err.out + err.err  # no episode ran
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    kept = target if existing == "file" else target / "notes.txt"
    assert kept.read_text() == "keep me"


def _episode(length=3, **overrides) -> lerobot.Episode:
    """A made-up episode of `FEATURES`, some frames replaced by `overrides`."""
    frames = {"observation.state": np.zeros((length, 2)), "next.reward": np.ones(length)}
    return lerobot.Episode({**frames, **overrides}, "open it", {"outcome": "fail"})


FEATURES = {
    "observation.state": {"dtype": "float32", "shape": [2], "names": ["a", "b"]},
    "next.reward": {"dtype": "float32", "shape": [1], "names": None},
}


@pytest.mark.parametrize(
    ("episodes", "message"),
    [
        ([], "at least one episode"),
        ([_episode(**{"observation.state": np.zeros((3, 4))})], "shape (4,), declared (2,)"),
        ([_episode(**{"next.reward": np.ones(2)})], "[2, 3] frames"),
        ([_episode(0)], "[0] frames"),
    ],
)
def test_bad_episodes_are_errors_and_write_nothing(tmp_path, episodes, message):
    with pytest.raises(RealIkeaError, match=re.escape(message)):
        lerobot.write_dataset(tmp_path / "ds", episodes, FEATURES, fps=10)
    assert list(tmp_path.iterdir()) == []


def test_an_interrupted_write_leaves_nothing(tmp_path, monkeypatch):
    def fail(*args, **kwargs):
        """A disk that fills up while the metadata is written."""
        raise OSError("disk full")

    monkeypatch.setattr(lerobot, "_write_json", fail)  # the last files of the folder
    with pytest.raises(OSError, match="disk full"):
        lerobot.write_dataset(tmp_path / "ds", [_episode()], FEATURES, fps=10)
    assert list(tmp_path.iterdir()) == []


def test_a_teleop_demonstration_converts_by_replaying_it(library, tmp_path):
    """A demonstration (recorded here from the heuristic pull through teleop's recorder) becomes
    a dataset whose frames are its observations and actions, with the replay's contact forces."""
    overrides = [*PIN, "dr=fixed", "task.episode_seconds=4", f"paths.library={library}"]
    cfg = load_config(overrides, "eval")
    (mjcf,) = training_configurations(cfg, 1, int(cfg.env.seed))
    task = OpenTask(cfg, mjcf, int(cfg.env.seed))
    recorder = Recorder(task, cfg, mjcf, int(cfg.env.seed), overrides, source="heuristic_pull")
    session, policy = Session(task, recorder), HeuristicPull.from_config(cfg)
    policy.reset([0], [task.facts()])
    while not recorder.finished:
        session.step(policy.act(session.obs[None])[0])
    demo = recorder.demonstration()
    recorder.save(tmp_path / "demo.npz")
    root = record_demonstration(tmp_path / "demo.npz", tmp_path / "demo", str(library))
    ds = read(root)
    (episode,) = demo.episodes
    (labels,) = ds["episodes"]
    assert labels["length"] == episode.steps == 40 and labels["policy"] == "replay"
    assert labels["config_id"] == CONFIG_ID and labels["outcome"] == episode.summary["outcome"]
    state = column(ds["data"], "observation.state")
    assert np.array_equal(state, episode.observations[:-1].astype(np.float32))
    assert np.array_equal(column(ds["data"], "action"), episode.actions.astype(np.float32))
    assert column(ds["data"], "contact.forces")[:, SAMPLE_FORCES.index("grip")].max() > 0


def test_every_category_has_words_for_its_instruction():
    assert set(PART_WORDS) == set(CATEGORIES)
    assert set(features()) == {
        "observation.state", "action", "next.reward", "next.done", "next.opening",
        "contact.forces",
    }  # fmt: skip
