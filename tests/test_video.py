"""`video=true`: one MP4 (and a PNG strip) per strategy observed, rendered on the CPU."""

from __future__ import annotations

import imageio.v2 as imageio

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.eval.video import record_strategies
from realikea.policies.heuristic_pull import HeuristicPull
from realikea.tasks.open_task import OpenTask


def test_one_video_and_strip_per_strategy(tmp_path):
    overrides = ["asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20", "dr=fixed"]
    cfg = load_config([*overrides, "task.contacts.log=true", "task.episode_seconds=8"])
    (mjcf,) = training_configurations(cfg, 1)
    written = record_strategies([OpenTask(cfg, mjcf)], HeuristicPull(), 2, tmp_path / "demo.mp4")
    assert list(written) == ["pinch"]  # both episodes pinch: the second adds no file
    (video,) = tmp_path.glob("*.mp4")
    assert video.name == "demo_pinch_success.mp4" and written["pinch"] == video
    frames = imageio.mimread(video)
    assert len(frames) == 80 and frames[0].shape == (
        384,
        512,
        3,
    )  # multiples of 16: no encoder padding
    strip = imageio.imread(video.with_suffix(".png"))
    assert strip.shape == (384, 4 * 512, 3)
    assert not list(tmp_path.glob(".*"))  # no temporary files left behind
