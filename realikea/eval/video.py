"""MP4s of a policy's episodes, rendered offscreen on the CPU: one per strategy observed."""

from __future__ import annotations

from pathlib import Path

import imageio.v2 as imageio
import mujoco
import numpy as np

from realikea.assets.cache import atomic_path
from realikea.tasks.open_task import OpenTask

FPS = 10  # one frame per control step (the policy runs at 10 Hz)


def episode_frames(task: OpenTask, policy, renderer: mujoco.Renderer) -> tuple[list, dict]:
    """Run one episode; its frames and its final info (outcome, strategy, ...)."""
    camera = task.model.camera("overview").id if task.model.ncam else -1
    obs, frames = task.reset(), []
    policy.reset(np.array([0]), [task.facts()])
    while True:
        renderer.update_scene(task.data, camera)
        frames.append(renderer.render())
        result = task.step(policy.act(obs[None])[0])
        obs = result.obs
        if result.terminated or result.truncated:
            return frames, result.info


def write_mp4(frames: list, path: Path) -> Path:
    """Write frames to an MP4 atomically (no half-written file on failure)."""
    path = Path(path)
    with (
        atomic_path(path) as tmp,
        imageio.get_writer(tmp, format="FFMPEG", fps=FPS, codec="libx264", quality=7) as writer,
    ):
        for frame in frames:
            writer.append_data(frame)
    return path


def write_strip(frames: list, path: Path, count: int = 4) -> Path:
    """`count` frames spread over an episode side by side in one PNG (for READMEs)."""
    picks = np.linspace(0, len(frames) - 1, count).round().astype(int)
    strip = np.concatenate([frames[i] for i in picks], axis=1)
    with atomic_path(path) as tmp:
        imageio.imwrite(tmp, strip, format="PNG")
    return path


def record_strategies(
    tasks: list[OpenTask], policy, episodes: int, stem: Path, size=(384, 512)
) -> dict[str, Path]:
    """Run up to `episodes` episodes (cycling over `tasks`) and write the first episode of each
    strategy label to `<stem>_<strategy>_<outcome>.mp4`, with a PNG strip of four of its frames
    next to it; returns label -> MP4 path."""
    written: dict[str, Path] = {}
    stem = Path(stem)
    for k in range(episodes):
        task = tasks[k % len(tasks)]
        with mujoco.Renderer(task.model, *size) as renderer:
            frames, info = episode_frames(task, policy, renderer)
        label = info.get("strategy", "episode")
        if label not in written:
            name = f"{stem.stem}_{label}_{info.get('outcome', 'fail')}.mp4"
            written[label] = write_mp4(frames, stem.with_name(name))
            write_strip(frames, written[label].with_suffix(".png"))
    return written
