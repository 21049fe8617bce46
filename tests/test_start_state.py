"""The start-state curricula (realikea/tasks/start_state.py): which episodes start at the
pre-grasp pose or with the front ajar, where the hand and the front then are, bad settings
refused before any work, and such episodes kept out of the training logs' success and out of
evaluations."""

from __future__ import annotations

import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.setup import effective_config
from realikea.tasks.open_task import OpenTask
from realikea.tasks.start_state import CURRICULUM_KEYS, AjarStart, PregraspStart
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
    "curriculum, extra, message",
    [
        (
            PregraspStart,
            ["+task.pregrasp_share=1.5"],
            r"pregrasp_share=1.5: use a share in \[0, 1\]",
        ),
        (PregraspStart, ["+task.pregrasp_groups=[fp_door]"], "unknown group fp_door"),
        (AjarStart, ["+task.ajar_share=-0.1"], r"task.ajar_share=-0.1: use a share in \[0, 1\]"),
        (AjarStart, ["+task.ajar_groups=[door]"], "unknown group door"),
        (AjarStart, ["+task.ajar_range=[0.9,0.4]"], r"task.ajar_range=\[0.9, 0.4\]"),
        (AjarStart, ["+task.ajar_range=[0.4,1.5]"], "0 <= low <= high <= 1"),
        (AjarStart, ["+task.ajar_range=0.5"], "task.ajar_range=0.5: use"),
    ],
)
def test_a_bad_setting_is_refused_by_name_before_any_work(curriculum, extra, message):
    cfg = load_config(extra)
    with pytest.raises(RealIkeaError, match=message):
        curriculum.from_config(cfg.task)
    with pytest.raises(RealIkeaError, match=message):
        check_inputs(cfg)


def test_an_ajar_episode_starts_with_the_front_open_inside_its_range_the_hand_at_home(door):
    _, home, _ = start(door)
    openings = []
    for seed in range(6):
        overrides, mjcf = door
        extra = ["+task.ajar_share=1.0", "+task.ajar_groups=[finger_pull_door]"]
        task = OpenTask(load_config([*overrides, *extra, "+task.ajar_range=[0.5,0.9]"]), mjcf, seed)
        task.reset()
        openings.append(task.opening / task._success)
        reach = task.data.site_xpos[task._tcp] - (task._nominal_handle + task._t1)
        assert np.linalg.norm(reach) == pytest.approx(home)  # the hand where it starts at home
        assert task.state.grasped and task.state.progress == pytest.approx(openings[-1])
        assert not task.data.qvel.any()
    assert all(0.5 <= f < 0.9 for f in openings) and len(set(openings)) == len(openings)


def test_an_ajar_start_pays_the_opening_it_keeps_and_charges_what_it_loses(door):
    """Counted as grasped, the level is paid from the first step and closing costs (the rate)."""
    extra = ["+task.ajar_share=1.0", "+task.ajar_range=[0.8,0.8]"]
    task, _, _ = start(door, *extra)
    first = task.step(np.zeros(task.action_size))
    closed, _, _ = start(door)
    assert first.reward > closed.step(np.zeros(closed.action_size)).reward
    assert task.state.term_sums["open"] > 0.0
    info = run_out(task)
    assert info["ajar"] is True and "ajar" in OpenTask.episode_keys
    assert "ajar" not in run_out(start(door)[0])


def test_with_both_curricula_an_episode_takes_the_pregrasp_start_first(door):
    task, distance, _ = start(door, "+task.pregrasp_share=1.0", "+task.ajar_share=1.0")
    assert distance < 0.005 and task.opening == pytest.approx(0.0, abs=1e-6)
    assert not task.state.ajar


def test_an_episode_begun_at_the_pregrasp_pose_says_so_and_others_do_not(door):
    task, _, _ = start(door, "+task.pregrasp_share=1.0")
    info = run_out(task)
    assert info["pregrasp"] is True and "pregrasp" in OpenTask.episode_keys
    assert "pregrasp" not in run_out(start(door)[0])


def run_out(task: OpenTask) -> dict:
    """The final info of an episode of zero actions."""
    while True:
        result = task.step(np.zeros(task.action_size))
        if result.terminated or result.truncated:
            return result.info


def test_training_logs_count_only_home_starts_and_show_curriculum_starts_apart(episode_log):
    episode = {"termination": "timeout", "opening": 0.0, "category": "knob", "kind": "door"}
    log = episode_log(
        [
            {**episode, "outcome": "fail", "stage": 1},
            {**episode, "outcome": "success", "stage": 4, "pregrasp": True},
            {**episode, "outcome": "partial", "stage": 4, "ajar": True},
        ]
    )
    assert log["/success/knob_door"].tolist() == [0.0]
    assert log["/episode/success"].tolist() == [0.0]
    assert log["/pregrasp_success/knob_door"].tolist() == [1.0]
    assert log["/ajar_success/knob_door"].tolist() == [0.0]


def test_an_evaluation_does_not_inherit_the_runs_curriculum():
    run_cfg = load_config(
        ["+task.pregrasp_share=0.5", "+task.pregrasp_groups=[knob_door]", "+task.ajar_share=0.3"]
        + ["+task.ajar_groups=[knob_door]", "+task.ajar_range=[0.4,0.9]"]
    )
    cfg = effective_config(load_config([], "eval"), run_cfg, [])
    assert not set(cfg.task) & set(CURRICULUM_KEYS)
    assert set(run_cfg.task) >= set(CURRICULUM_KEYS)
    assert cfg.task.reward == run_cfg.task.reward  # the rest of the run's task is kept
