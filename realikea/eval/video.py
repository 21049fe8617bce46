"""MP4 of a policy's episodes, rendered offscreen on the CPU."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import imageio.v2 as imageio
import mujoco
import numpy as np

from realikea.tasks.open_task import OpenTask

FPS = 10  # one frame per control step (the policy runs at 10 Hz)


def record(task: OpenTask, policy, episodes: int, path: Path, size=(480, 640)) -> Path:
    """Run `episodes` episodes of `policy` on `task` and write them to one MP4 (atomically)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    renderer = mujoco.Renderer(task.model, *size)
    camera = task.model.camera("overview").id if task.model.ncam else -1
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".mp4")
    os.close(fd)
    try:
        with imageio.get_writer(tmp, fps=FPS, codec="libx264", quality=7) as writer:
            for _ in range(episodes):
                obs, done = task.reset(), False
                policy.reset(np.array([0]))
                while not done:
                    renderer.update_scene(task.data, camera)
                    writer.append_data(renderer.render())
                    result = task.step(policy.act(obs[None])[0])
                    obs, done = result.obs, result.terminated or result.truncated
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    finally:
        renderer.close()
        Path(tmp).unlink(missing_ok=True)
    return path
