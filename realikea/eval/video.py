"""MP4s of a policy's episodes, rendered offscreen on the CPU: one per strategy observed."""

from __future__ import annotations

import math
from pathlib import Path

import imageio.v2 as imageio
import mujoco
import numpy as np

from realikea.assets.library import training_configurations
from realikea.files import atomic_path
from realikea.tasks.open_task import OpenTask

FPS = 10  # one frame per control step (the policy runs at 10 Hz)
CLOSE_UP_DISTANCE = 0.45  # m from the handle
CLOSE_UP_ELEVATION_DEG = -35.0  # looking down on the handle
CLOSE_UP_AZIMUTH_DEG = -60.0  # turned from straight-on, away from the robot's side


def close_up(task: OpenTask) -> mujoco.MjvCamera:
    """A free camera 0.45 m from the handle, outside the front, beside and above it, looking at
    where the gripper meets the part (its direction set at the episode's start; it follows
    the handle as the front opens)."""
    facts = task.facts()
    u = facts.pull_dir
    camera = mujoco.MjvCamera()
    camera.type = mujoco.mjtCamera.mjCAMERA_FREE
    camera.lookat[:] = facts.handle_pos
    camera.distance = CLOSE_UP_DISTANCE
    camera.elevation = CLOSE_UP_ELEVATION_DEG
    camera.azimuth = math.degrees(math.atan2(-u[1], -u[0])) + CLOSE_UP_AZIMUTH_DEG
    return camera


def episode_frames(task: OpenTask, policy, renderer: mujoco.Renderer) -> tuple[list, dict]:
    """Run one episode; its frames (the overview above a close-up of the handle) and its final
    info (outcome, strategy, ...)."""
    overview = task.model.camera("overview").id if task.model.ncam else -1
    obs, frames = task.reset(), []
    policy.reset(np.array([0]), [task.facts()])
    handle = close_up(task)
    while True:
        views = []
        handle.lookat[:] = task.facts().handle_pos
        for camera in (overview, handle):
            renderer.update_scene(task.data, camera)
            views.append(renderer.render())
        frames.append(np.concatenate(views, axis=0))
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


VIDEO_BY = ("strategy", "outcome")  # what one recorded episode stands for (`video_by`)


def record_episodes(
    tasks: list[OpenTask], policy, episodes: int, stem: Path, by: str = "strategy", size=(384, 512)
) -> dict[str, Path]:
    """Run up to `episodes` episodes (cycling over `tasks`) and write MP4s with a PNG strip of
    four of their frames next to each; returns key -> MP4 path. Each frame is `size` (height,
    width) per view, two views.

    by="strategy": one episode of each strategy label, its first success if there is one, else
    its first episode, to `<stem>_<strategy>_<outcome>.mp4`. by="outcome": the first success and
    the first failure (fail or partial), to `<stem>_<outcome>_<strategy>.mp4`, stopping once
    both are written."""
    if by not in VIDEO_BY:
        raise ValueError(f"video_by={by}: use one of {', '.join(VIDEO_BY)}")
    written: dict[str, Path] = {}
    stem = Path(stem)
    for k in range(episodes):
        task = tasks[k % len(tasks)]
        with mujoco.Renderer(task.model, *size) as renderer:
            frames, info = episode_frames(task, policy, renderer)
        label, outcome = info.get("strategy", "episode"), info.get("outcome", "fail")
        if by == "outcome":
            key, name = ("success" if outcome == "success" else "failure"), f"{outcome}_{label}"
        else:
            key, name = label, f"{label}_{outcome}"
        kept = written.get(key)
        replaces = by == "strategy" and outcome == "success"  # a label's first success
        if kept is not None and not (replaces and not kept.stem.endswith("_success")):
            continue
        path = write_mp4(frames, stem.with_name(f"{stem.stem}_{name}.mp4"))
        write_strip(frames, path.with_suffix(".png"))
        if kept is not None:  # a failure of this label, now replaced by a success
            kept.unlink()
            kept.with_suffix(".png").unlink()
        written[key] = path
        if by == "outcome" and len(written) == 2:
            break
    return written


def drawn_tasks(cfg, count: int) -> list[OpenTask]:
    """The first `count` configurations drawn as the evaluation draws them (`cfg.env.seed`),
    each as a task seeded `cfg.env.seed` plus its index: the episodes videos show."""
    seed = int(cfg.env.seed)
    paths = training_configurations(cfg, count, seed)
    return [OpenTask(cfg, path, seed + i) for i, path in enumerate(paths)]


def record_draw(cfg, policy, stem: Path) -> dict[str, Path]:
    """`record_episodes` on the configured draw (`drawn_tasks`): `cfg.video_episodes` episodes,
    recorded by `cfg.video_by`; prints and returns key -> MP4."""
    count = int(cfg.video_episodes)
    recorded = record_episodes(drawn_tasks(cfg, count), policy, count, stem, cfg.video_by)
    for key, path in recorded.items():
        print(f"video ({key}): {path}")
    return recorded
