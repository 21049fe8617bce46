"""`video=true`: one MP4 (and a PNG strip) per strategy observed, or a success and a failure,
rendered on the CPU."""

from __future__ import annotations

from types import SimpleNamespace

import imageio.v2 as imageio
import mujoco
import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.cli import main
from realikea.config import load_config
from realikea.eval import video as video_module
from realikea.eval.video import record_episodes
from realikea.policies.heuristic_pull import HeuristicPull
from realikea.tasks.open_task import OpenTask


def test_one_video_and_strip_per_strategy(tmp_path):
    overrides = ["asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20", "dr=fixed"]
    cfg = load_config([*overrides, "task.episode_seconds=8"], "eval")
    (mjcf,) = training_configurations(cfg, 1)
    written = record_episodes([OpenTask(cfg, mjcf)], HeuristicPull(), 2, tmp_path / "demo.mp4")
    assert list(written) == ["pinch"]  # both episodes pinch: the second adds no file
    (video,) = tmp_path.glob("*.mp4")
    assert video.name == "demo_pinch_success.mp4" and written["pinch"] == video
    frames = imageio.mimread(video)
    # the overview above the close-up; multiples of 16: no encoder padding
    assert len(frames) == 80 and frames[0].shape == (2 * 384, 512, 3)
    strip = imageio.imread(video.with_suffix(".png"))
    assert strip.shape == (2 * 384, 4 * 512, 3)
    assert not list(tmp_path.glob(".*"))  # no temporary files left behind


def test_a_later_success_replaces_the_first_failure_of_a_label(tmp_path, monkeypatch):
    """Per label the first success is kept (else the first episode): the strip shows the
    strategy working, not its first attempt."""
    infos = iter(
        [
            {"strategy": "hook", "outcome": "fail"},
            {"strategy": "pinch", "outcome": "partial"},
            {"strategy": "hook", "outcome": "success"},
            {"strategy": "hook", "outcome": "success"},
            {"strategy": "pinch", "outcome": "fail"},
        ]
    )
    frames = [np.full((32, 48, 3), k * 40, np.uint8) for k in range(5)]
    monkeypatch.setattr(video_module, "episode_frames", lambda *_: (frames, next(infos)))
    task = SimpleNamespace(model=mujoco.MjModel.from_xml_string("<mujoco/>"))
    written = record_episodes([task], None, 5, tmp_path / "ep.mp4", size=(32, 48))
    assert {k: p.name for k, p in written.items()} == {
        "hook": "ep_hook_success.mp4",
        "pinch": "ep_pinch_partial.mp4",
    }
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == [
        "ep_hook_success.mp4",
        "ep_hook_success.png",
        "ep_pinch_partial.mp4",
        "ep_pinch_partial.png",
    ]


def test_by_outcome_the_first_success_and_the_first_failure(tmp_path, monkeypatch):
    infos = iter(
        [
            {"strategy": "hook", "outcome": "success"},
            {"strategy": "pinch", "outcome": "success"},
            {"strategy": "pinch", "outcome": "partial"},
            {"strategy": "hook", "outcome": "fail"},
        ]
    )
    frames = [np.full((32, 48, 3), k * 40, np.uint8) for k in range(5)]
    monkeypatch.setattr(video_module, "episode_frames", lambda *_: (frames, next(infos)))
    task = SimpleNamespace(model=mujoco.MjModel.from_xml_string("<mujoco/>"))
    written = record_episodes([task], None, 4, tmp_path / "ep.mp4", "outcome", size=(32, 48))
    assert {k: p.name for k, p in written.items()} == {
        "success": "ep_success_hook.mp4",
        "failure": "ep_partial_pinch.mp4",
    }
    assert next(infos, None) == {"strategy": "hook", "outcome": "fail"}  # stopped after both
    with pytest.raises(ValueError, match="video_by=label: use one of strategy, outcome"):
        record_episodes([task], None, 4, tmp_path / "ep.mp4", "label")


def test_an_unknown_video_by_fails_before_any_episode(capsys):
    part = ["asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20"]
    assert main(["eval", "policy=heuristic_pull", *part, "video=true", "video_by=label"]) == 2
    assert "video_by=label: use one of strategy, outcome" in capsys.readouterr().err
