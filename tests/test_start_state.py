"""The start-state curriculum (realikea/tasks/start_state.py): which episodes start at the
pre-grasp pose, where the hand then is, and bad settings refused before any work."""

from __future__ import annotations

import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.tasks.open_task import OpenTask
from realikea.tasks.start_state import PregraspStart
from realikea.training.train import check_inputs

PIN = ["asset=finger_pull", "asset.part=fp_cup_128", "asset.base=door_left_w40_h80", "dr=fixed"]


@pytest.fixture(scope="module")
def door(tmp_path_factory):
    """A built finger-pull door and the overrides that simulate it."""
    overrides = [*PIN, f"paths.library={tmp_path_factory.mktemp('library')}"]
    (mjcf,) = training_configurations(load_config(overrides), 1)
    return overrides, mjcf


def start(door, *extra) -> tuple[OpenTask, np.ndarray, dict]:
    """A task of `door` with `extra` overrides after one reset: the TCP's distance to the
    pre-grasp target, and the rng's state before the reset."""
    overrides, mjcf = door
    task = OpenTask(load_config([*overrides, *extra]), mjcf, seed=0)
    before = task.rng.bit_generator.state
    task.reset()
    target = task._nominal_handle + task._t1
    return task, np.linalg.norm(task.data.site_xpos[task._tcp] - target), before


def test_a_curriculum_episode_starts_with_the_tcp_at_the_pregrasp_target(door):
    task, distance, _ = start(
        door, "+task.pregrasp_share=1.0", "+task.pregrasp_groups=[finger_pull_door]"
    )
    assert distance < 0.005
    assert not task.data.qvel.any()  # placed there at rest, not moving


def test_without_it_or_outside_its_groups_the_hand_starts_at_home(door):
    _, home, before = start(door)
    assert home > 0.05
    task, _, _ = start(door)
    assert task.rng.bit_generator.state == before  # no random number drawn for it
    _, other, _ = start(door, "+task.pregrasp_share=1.0", "+task.pregrasp_groups=[knob_door]")
    assert other == pytest.approx(home)


@pytest.mark.parametrize(
    "extra, message",
    [
        (["+task.pregrasp_share=1.5"], r"task.pregrasp_share=1.5: use a share in \[0, 1\]"),
        (["+task.pregrasp_share=0.3", "+task.pregrasp_groups=[fp_door]"], "unknown group fp_door"),
    ],
)
def test_a_bad_setting_is_refused_by_name_before_any_work(extra, message):
    cfg = load_config(extra)
    with pytest.raises(RealIkeaError, match=message):
        PregraspStart.from_config(cfg.task)
    with pytest.raises(RealIkeaError, match=message):
        check_inputs(cfg)
