"""A LeRobotDataset in format v3.0 written with pyarrow alone (no lerobot, datasets or pandas).

The layout is lerobot 0.4's (`CODEBASE_VERSION = "v3.0"` in lerobot/datasets/lerobot_dataset.py,
the paths and `DEFAULT_FEATURES` in lerobot/datasets/utils.py, the stats in
lerobot/datasets/compute_stats.py):

    meta/info.json                              codebase_version, fps, features, totals, paths
    meta/stats.json                             per feature: min max mean std count q01 ... q99
    meta/tasks.parquet                          task (the pandas index) -> task_index
    meta/episodes/chunk-000/file-000.parquet    a row per episode: tasks, length, where its
                                                frames are, stats/<feature>/<stat>, the labels
    data/chunk-000/file-000.parquet             a row per frame: every feature

Every frame lives in one data file (lerobot starts another past `data_files_size_in_mb`, 100 MB:
about 600,000 frames of 40 numbers). There are no videos. A vector feature is a fixed-size list
column, a feature of shape (1,) a plain column, as lerobot's `get_hf_features_from_features`
declares them. Quantiles are exact (`np.quantile`), where lerobot approximates them with
histograms; the dataset's stats are computed over all frames. Episode labels (any columns the
caller adds) sit beside lerobot's own columns in the episodes table.

The folder is written through a staging folder and appears whole or not at all.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from realikea.errors import RealIkeaError
from realikea.files import staging_dir

CODEBASE_VERSION = "v3.0"
CHUNKS_SIZE = 1000  # lerobot's DEFAULT_CHUNK_SIZE: files per chunk folder
DATA_FILES_SIZE_IN_MB = 100
VIDEO_FILES_SIZE_IN_MB = 200
DATA_PATH = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
EPISODES_PATH = "meta/episodes/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet"
# the columns lerobot adds to every frame
DEFAULT_FEATURES = {
    "timestamp": {"dtype": "float32", "shape": [1], "names": None},
    "frame_index": {"dtype": "int64", "shape": [1], "names": None},
    "episode_index": {"dtype": "int64", "shape": [1], "names": None},
    "index": {"dtype": "int64", "shape": [1], "names": None},
    "task_index": {"dtype": "int64", "shape": [1], "names": None},
}
QUANTILES = (0.01, 0.10, 0.50, 0.90, 0.99)  # stats keys q01, q10, q50, q90, q99
ARROW_TYPES = {
    "float32": pa.float32(),
    "float64": pa.float64(),
    "int64": pa.int64(),
    "bool": pa.bool_(),
}
# tasks.parquet is a pandas frame indexed by the task string (lerobot reads it with pandas)
TASKS_PANDAS_METADATA = {
    "index_columns": ["task"],
    "column_indexes": [],
    "columns": [
        {"name": "task", "field_name": "task", "pandas_type": "unicode", "numpy_type": "object",
         "metadata": None},
        {"name": "task_index", "field_name": "task_index", "pandas_type": "int64",
         "numpy_type": "int64", "metadata": None},
    ],
}  # fmt: skip


@dataclass(frozen=True)
class Episode:
    """One episode: every feature's values per frame (T rows each), the task it performed (an
    instruction in words) and its labels (columns of the episodes table)."""

    frames: dict[str, np.ndarray]
    task: str
    labels: dict


def check_target(root: Path) -> Path:
    """`root` as a dataset folder to write: new, or an empty folder; otherwise a RealIkeaError."""
    root = Path(root)
    if root.exists() and not root.is_dir():
        raise RealIkeaError(f"{root} is a file, not a folder for a LeRobot dataset")
    if root.is_dir() and any(root.iterdir()):
        raise RealIkeaError(f"{root} is not empty: name a new folder for the LeRobot dataset")
    return root


def write_dataset(
    root: Path, episodes: list[Episode], features: dict, fps: int, robot_type: str | None = None
) -> Path:
    """Write `episodes` as a LeRobotDataset v3.0 at `root` (a new or empty folder).

    `features` maps each per-frame feature to `{"dtype", "shape", "names"}` (1-D shapes; dtypes
    float32, float64, int64 or bool), as lerobot's `LeRobotDataset.create` takes them.
    """
    root = check_target(root)
    features = {name: dict(ft, shape=list(ft["shape"])) for name, ft in features.items()}
    _check_episodes(episodes, features)
    tasks = list(dict.fromkeys(e.task for e in episodes))
    columns, rows = _frame_columns(episodes, features, tasks, fps)
    every = {**features, **DEFAULT_FEATURES}
    episode_stats = [_stats(_slice(columns, start, stop), every) for start, stop in rows]
    with staging_dir(root) as tmp:
        data = tmp / DATA_PATH.format(chunk_index=0, file_index=0)
        data.parent.mkdir(parents=True)
        pq.write_table(_table(columns, every), data, compression="snappy")
        (tmp / "meta").mkdir()
        _write_tasks(tmp / "meta" / "tasks.parquet", tasks)
        table = _episodes_table(episodes, tasks, rows, episode_stats)
        path = tmp / EPISODES_PATH.format(chunk_index=0, file_index=0)
        path.parent.mkdir(parents=True)
        pq.write_table(table, path, compression="snappy")
        info = _info(every, fps, robot_type, len(episodes), rows[-1][1], len(tasks))
        _write_json(tmp / "meta" / "info.json", info)
        _write_json(tmp / "meta" / "stats.json", _stats(columns, every))
    return root


def _check_episodes(episodes: list[Episode], features: dict) -> None:
    """Every episode has every feature with its shape and at least one frame."""
    if not episodes:
        raise RealIkeaError("a LeRobot dataset needs at least one episode")
    for name, ft in features.items():
        if name in DEFAULT_FEATURES or "/" in name:
            raise RealIkeaError(f"feature {name!r}: a name of lerobot's own or with '/'")
        if ft["dtype"] not in ARROW_TYPES or len(ft["shape"]) != 1:
            raise RealIkeaError(
                f"feature {name!r}: {ft['dtype']} {ft['shape']}; this writer takes 1-D "
                f"{', '.join(ARROW_TYPES)} features"
            )
    for k, episode in enumerate(episodes):
        lengths = set()
        for name, ft in features.items():
            if name not in episode.frames:
                raise RealIkeaError(f"episode {k} lacks feature {name!r}")
            values = np.asarray(episode.frames[name])
            size = ft["shape"][0]
            if values.shape[1:] not in ([(size,), ()] if size == 1 else [(size,)]):
                raise RealIkeaError(
                    f"episode {k}: feature {name!r} has frames of shape {values.shape[1:]}, "
                    f"declared {tuple(ft['shape'])}"
                )
            lengths.add(len(values))
        if len(lengths) != 1 or 0 in lengths:
            raise RealIkeaError(f"episode {k}: its features have {sorted(lengths)} frames")


def _frame_columns(episodes, features, tasks, fps) -> tuple[dict, list[tuple[int, int]]]:
    """Every feature's values over all frames, episodes one after another, lerobot's own columns
    included; and each episode's [from, to) frame rows."""
    columns: dict[str, list] = {name: [] for name in (*features, *DEFAULT_FEATURES)}
    rows, start = [], 0
    for k, episode in enumerate(episodes):
        length = len(next(iter(episode.frames.values())))
        for name, ft in features.items():
            values = np.asarray(episode.frames[name], dtype=ft["dtype"])
            columns[name].append(values.reshape(length, ft["shape"][0]))
        frame = np.arange(length)
        columns["timestamp"].append((frame / fps).astype(np.float32))
        columns["frame_index"].append(frame)
        columns["episode_index"].append(np.full(length, k))
        columns["index"].append(start + frame)
        columns["task_index"].append(np.full(length, tasks.index(episode.task)))
        rows.append((start, start + length))
        start += length
    return {name: np.concatenate(parts) for name, parts in columns.items()}, rows


def _slice(columns: dict, start: int, stop: int) -> dict:
    """The frames [start, stop) of every column."""
    return {name: values[start:stop] for name, values in columns.items()}


def _table(columns: dict, features: dict) -> pa.Table:
    """The frames as arrow columns: plain for shape (1,), fixed-size lists otherwise."""
    arrays = {}
    for name, ft in features.items():
        kind, values = ARROW_TYPES[ft["dtype"]], columns[name]
        size = ft["shape"][0]
        if size == 1:
            arrays[name] = pa.array(values.reshape(-1), type=kind)
        else:
            flat = pa.array(values.reshape(-1), type=kind)
            arrays[name] = pa.FixedSizeListArray.from_arrays(flat, size)
    return pa.table(arrays)


def _stats(columns: dict, features: dict) -> dict[str, dict[str, list]]:
    """lerobot's statistics of every feature over the given frames (shape (n,) each)."""
    out = {}
    for name, ft in features.items():
        values = columns[name].astype(np.float64).reshape(len(columns[name]), ft["shape"][0])
        stats = {
            "min": values.min(axis=0),
            "max": values.max(axis=0),
            "mean": values.mean(axis=0),
            "std": values.std(axis=0),
        }
        for q in QUANTILES:
            stats[f"q{round(q * 100):02d}"] = np.quantile(values, q, axis=0)
        out[name] = {key: value.tolist() for key, value in stats.items()}
        out[name]["count"] = [len(values)]
    return out


def _episodes_table(episodes, tasks, rows, episode_stats) -> pa.Table:
    """A row per episode: lerobot's columns (where its frames are, its stats), then the labels."""
    columns: dict[str, list] = {
        "episode_index": list(range(len(episodes))),
        "tasks": [[e.task] for e in episodes],
        "length": [stop - start for start, stop in rows],
        "data/chunk_index": [0] * len(episodes),
        "data/file_index": [0] * len(episodes),
        "dataset_from_index": [start for start, _ in rows],
        "dataset_to_index": [stop for _, stop in rows],
        "meta/episodes/chunk_index": [0] * len(episodes),
        "meta/episodes/file_index": [0] * len(episodes),
    }
    for feature, stats in episode_stats[0].items():
        for key in stats:
            columns[f"stats/{feature}/{key}"] = [s[feature][key] for s in episode_stats]
    labels = list(dict.fromkeys(key for e in episodes for key in e.labels))
    clash = [key for key in labels if key in columns]
    if clash:
        raise RealIkeaError(f"episode labels {clash} would replace lerobot's own columns")
    arrays = {name: pa.array(values) for name, values in columns.items()}
    for key in labels:
        array = pa.array([e.labels.get(key) for e in episodes])
        arrays[key] = array.cast(pa.string()) if pa.types.is_null(array.type) else array
    return pa.table(arrays)


def _write_tasks(path: Path, tasks: list[str]) -> None:
    """meta/tasks.parquet: task -> task_index, the task marked as the pandas index."""
    table = pa.table({"task": tasks, "task_index": pa.array(range(len(tasks)), pa.int64())})
    metadata = {b"pandas": json.dumps(TASKS_PANDAS_METADATA).encode()}
    pq.write_table(table.replace_schema_metadata(metadata), path)


def _info(features, fps, robot_type, episodes, frames, tasks) -> dict:
    """meta/info.json as lerobot's `create_empty_dataset_info` lays it out, totals filled in."""
    return {
        "codebase_version": CODEBASE_VERSION,
        "robot_type": robot_type,
        "total_episodes": episodes,
        "total_frames": frames,
        "total_tasks": tasks,
        "chunks_size": CHUNKS_SIZE,
        "data_files_size_in_mb": DATA_FILES_SIZE_IN_MB,
        "video_files_size_in_mb": VIDEO_FILES_SIZE_IN_MB,
        "fps": int(fps),
        "splits": {"train": f"0:{episodes}"},
        "data_path": DATA_PATH,
        "video_path": None,
        "features": features,
    }


def _write_json(path: Path, data: dict) -> None:
    """A JSON file indented as lerobot writes its own."""
    path.write_text(json.dumps(data, indent=4) + "\n")
