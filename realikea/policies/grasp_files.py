"""Grasp files for `grasp_sampler` (`policy.grasps=PATH`), e.g. from a learned grasp predictor.

A grasp is a TCP pose in the part frame (metres; the part frame's z points out of the front):
rotation columns are the TCP axes x (across the jaws), y (the jaw closing axis), z (the approach,
pointing into the part); the translation is the TCP, midway between the pads at the pad centre.
Either

- a 4x4 homogeneous matrix (last row 0 0 0 1), or
- 7 numbers: position x y z then quaternion w x y z (MuJoCo's order; normalized on load),
  or in JSON also {"position": [x, y, z], "quaternion": [w, x, y, z]} or {"pose": 4x4}.

Files: `.json` holding one list of grasps (used for every part) or an object mapping part ids to
lists; `.npy` holding one array (N, 4, 4) or (N, 7) for every part; `.npz` with one such array
per part id. Grasps are tried in file order (first = best); the first one whose world pitch is in
range is executed. The hand is symmetric under a half turn about the approach, so a rotation and
the same rotation turned by 180 deg about its z are the same grasp. A malformed file (wrong shape,
non-finite values, non-orthonormal rotation, unknown part id, no grasps for the episode's part, a
rotation the fixed roll/yaw cannot reach within `reach_tolerance` rad) raises `RealIkeaError`.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from realikea.errors import RealIkeaError


def _poses(values, path: Path, where: str) -> np.ndarray:
    """(N, 4, 4) part-frame poses from an array-like of 4x4 matrices or 7-vectors."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as error:
        raise RealIkeaError(f"grasp file {path}: {where} is not numeric ({error})") from None
    if array.ndim == 2 and array.shape[1] == 7:
        poses = np.tile(np.eye(4), (len(array), 1, 1))
        if not np.all(np.isfinite(array)):
            raise RealIkeaError(f"grasp file {path}: {where} holds non-finite values")
        norm = np.linalg.norm(array[:, 3:], axis=1)
        if np.any(norm < 1e-9):
            raise RealIkeaError(f"grasp file {path}: {where} holds a zero quaternion")
        q = array[:, 3:] / norm[:, None]
        for k in range(len(array)):
            poses[k, :3, :3] = _quat_matrix(q[k])
        poses[:, :3, 3] = array[:, :3]
        array = poses
    if array.ndim != 3 or array.shape[1:] != (4, 4) or len(array) == 0:
        raise RealIkeaError(
            f"grasp file {path}: {where} must be a non-empty list of 4x4 poses or of 7-vectors "
            f"(x y z qw qx qy qz), got shape {array.shape}"
        )
    if not np.all(np.isfinite(array)):
        raise RealIkeaError(f"grasp file {path}: {where} holds non-finite values")
    for k, pose in enumerate(array):
        if not np.allclose(pose[3], [0.0, 0.0, 0.0, 1.0], atol=1e-6):
            raise RealIkeaError(f"grasp file {path}: {where}[{k}] last row is not 0 0 0 1")
        r = pose[:3, :3]
        if not np.allclose(r.T @ r, np.eye(3), atol=1e-4) or np.linalg.det(r) < 0.0:
            raise RealIkeaError(
                f"grasp file {path}: {where}[{k}] rotation is not orthonormal and right-handed"
            )
    return array


def _quat_matrix(q) -> np.ndarray:
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _json_grasp(item):
    if isinstance(item, dict):
        if "pose" in item:
            return np.asarray(item["pose"], dtype=float).reshape(-1).tolist()
        if "position" in item and "quaternion" in item:
            return [*item["position"], *item["quaternion"]]
        raise RealIkeaError("a JSON grasp object needs 'pose' or 'position' and 'quaternion'")
    return item


def _json_list(items, path: Path, where: str) -> np.ndarray:
    if not isinstance(items, list):
        raise RealIkeaError(f"grasp file {path}: {where} must be a list of grasps")
    try:
        flat = [_json_grasp(g) for g in items]
    except RealIkeaError as error:
        raise RealIkeaError(f"grasp file {path}: {where}: {error}") from None
    try:
        array = np.asarray(flat, dtype=float)
    except (TypeError, ValueError) as error:
        raise RealIkeaError(f"grasp file {path}: {where} is not numeric ({error})") from None
    if array.ndim == 2 and array.shape[1] == 16:
        array = array.reshape(-1, 4, 4)
    return _poses(array, path, where)


def load_grasp_file(path, part_ids=None) -> dict[str | None, np.ndarray]:
    """Grasp poses from a file: {part id: (N, 4, 4)}, or {None: poses} for every part.
    `part_ids` (known ids) rejects keys that name no part."""
    path = Path(path)
    if not path.is_file():
        raise RealIkeaError(f"grasp file {path} does not exist")
    suffix = path.suffix.lower()
    try:
        if suffix == ".json":
            data = json.loads(path.read_text())
            if isinstance(data, dict):
                table = {str(k): _json_list(v, path, f"part {k!r}") for k, v in data.items()}
            else:
                table = {None: _json_list(data, path, "the grasp list")}
        elif suffix == ".npy":
            table = {None: _poses(np.load(path, allow_pickle=False), path, "the array")}
        elif suffix == ".npz":
            with np.load(path, allow_pickle=False) as archive:
                table = {k: _poses(archive[k], path, f"part {k!r}") for k in archive.files}
        else:
            raise RealIkeaError(f"grasp file {path}: use .json, .npy or .npz, not {suffix!r}")
    except RealIkeaError:
        raise
    except (OSError, ValueError) as error:
        raise RealIkeaError(f"grasp file {path} cannot be read: {error}") from None
    if not table:
        raise RealIkeaError(f"grasp file {path} holds no grasps")
    if part_ids is not None:
        unknown = [k for k in table if k is not None and k not in part_ids]
        if unknown:
            raise RealIkeaError(f"grasp file {path}: unknown part id(s) {', '.join(unknown)}")
    return table


def save_grasp_file(path, grasps: dict[str | None, np.ndarray]) -> None:
    """Write poses ({part id: (N, 4, 4)} or {None: (N, 4, 4)}) as JSON (4x4 nested lists)."""
    if None in grasps:
        data = np.asarray(grasps[None]).tolist()
    else:
        data = {k: np.asarray(v).tolist() for k, v in grasps.items()}
    Path(path).write_text(json.dumps(data))
