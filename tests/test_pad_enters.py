"""Which finger pulls the fingertip pad fits (realikea/tasks/open_task.py `pad_enters`): on the
task and its episodes' end info, and in the training logs, where finger-pull groups show their
success on those parts apart (`/pad_enters_success/<group>`)."""

from __future__ import annotations

import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.tasks.open_task import OpenTask


def task_of(library, category: str, part: str, base: str = "door_left_w40_h80") -> OpenTask:
    overrides = [f"asset={category}", f"asset.part={part}", f"asset.base={base}", "dr=fixed",
                 f"paths.library={library}"]  # fmt: skip
    cfg = load_config(overrides)
    (mjcf,) = training_configurations(cfg, 1)
    return OpenTask(cfg, mjcf, seed=0)


@pytest.mark.parametrize(
    "category, part, fits",
    [
        ("finger_pull", "fp_cup_128", True),  # a 15.0 mm channel
        ("finger_pull", "fp_edge_96_slim", False),  # 6.0 mm, under the 9 mm pad
        ("knob", "knob_cylindrical_30", True),  # not measured: counts as fitting
    ],
)
def test_a_finger_pull_fits_the_pad_when_its_channel_is_as_wide(tmp_path, category, part, fits):
    assert task_of(tmp_path, category, part).pad_enters is fits


def test_an_episodes_end_says_whether_the_pad_fits(tmp_path):
    task = task_of(tmp_path, "finger_pull", "fp_edge_96_slim")
    assert "pad_enters" in task.episode_keys
    task.reset()
    info = {}
    while "outcome" not in info:
        info = task.step(np.zeros(task.action_size)).info
    assert info["pad_enters"] is False


def test_training_logs_show_finger_pull_success_on_parts_the_pad_enters(episode_log):
    door = {"termination": "timeout", "opening": 0.0, "category": "finger_pull", "kind": "door"}
    log = episode_log(
        [
            {**door, "outcome": "success", "stage": 4, "pad_enters": True},
            {**door, "outcome": "fail", "stage": 1, "pad_enters": True},
            {**door, "outcome": "fail", "stage": 1, "pad_enters": False},
            {**door, "outcome": "success", "stage": 4, "pad_enters": True, "ajar": True},
            {**door, "category": "knob", "outcome": "success", "stage": 4, "pad_enters": True},
        ]
    )
    assert log["/success/finger_pull_door"].tolist() == [1.0, 0.0, 0.0]
    assert log["/pad_enters_success/finger_pull_door"].tolist() == [1.0, 0.0]
    assert "/pad_enters_success/knob_door" not in log
