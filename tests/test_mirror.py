"""The mirror (`task.mirror_doors`): a left-hinged door seen and driven as its right-hinged twin."""

from __future__ import annotations

import numpy as np
import pytest
from omegaconf import OmegaConf

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.setup import effective_config, eval_setup
from realikea.policies.heuristic_pull import HeuristicPull
from realikea.tasks import mirror, observations
from realikea.tasks.open_task import OpenTask
from realikea.tasks.recording import RecordingTask


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    return tmp_path_factory.mktemp("library")


def _task(library, part: str, base: str, mirrored: bool, task_class=OpenTask) -> OpenTask:
    """One configuration's task, poses fixed, the mirror on or off (contacts logged, as a
    recording needs)."""
    cfg = load_config(
        [f"asset.part={part}", f"asset.base={base}", "dr=fixed", f"paths.library={library}",
         f"task.mirror_doors={str(mirrored).lower()}", "contacts.log=true"],
        "eval",
    )  # fmt: skip
    return task_class(cfg, training_configurations(cfg, 1, 0)[0])


def test_every_reflected_term_is_an_observation_term():
    names = {name for name, _ in observations.LAYOUT}
    assert set(mirror.TERM_SIGNS) <= names
    assert mirror.OBSERVATION_SIGNS.shape == (observations.SIZE,)


@pytest.mark.parametrize(
    ("part", "base", "mirrored"),
    [
        ("tp_round_bar_128", "door_left_w40_h80", True),
        ("tp_round_bar_128", "door_right_w40_h80", False),
        ("fp_edge_96", "door_right_w40_h80", True),  # the placement turns the hand: right mirrors
        ("fp_edge_96", "door_left_w40_h80", False),
        ("tp_round_bar_128", "drawer_w60_h20", False),
        ("tp_round_bar_128", "flap_w60_h40", False),
    ],
)
def test_the_doors_whose_arm_starts_mirrored_are_the_mirrored_ones(library, part, base, mirrored):
    assert _task(library, part, base, True).mirrored is mirrored
    assert _task(library, part, base, False).mirrored is False  # off by default


def _heuristic_episode(task: OpenTask) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The heuristic pull's episode on `task`: its observations and actions."""
    policy = HeuristicPull.from_config(load_config(["policy=heuristic_pull"], "eval"))
    obs = [task.reset()]
    policy.reset([0], [task.facts()])
    actions = []
    for _ in range(task.horizon):
        actions.append(policy.act(obs[-1][None])[0])
        result = task.step(actions[-1])
        obs.append(result.obs)
        if result.terminated or result.truncated:
            break
    return obs, actions


@pytest.mark.parametrize("mirrored", [True, False])
def test_a_left_door_replays_its_right_twin_reflected(library, mirrored):
    """The heuristic pull opens the right-hinged door; its actions, replayed on the left-hinged
    twin with the mirror on, open it as far with the same observations (the physics reflects);
    with the mirror off the same actions open nothing."""
    right = _task(library, "tp_round_bar_128", "door_right_w40_h80", False)
    obs, actions = _heuristic_episode(right)
    assert right.opening > 1.0  # rad: past success (0.785)
    left = _task(library, "tp_round_bar_128", "door_left_w40_h80", mirrored)
    seen = [left.reset()] + [left.step(a).obs for a in actions]
    gap = max(float(np.abs(a - b).max()) for a, b in zip(seen, obs, strict=True))
    if mirrored:
        assert gap < 0.01 and left.opening == pytest.approx(right.opening, abs=0.01)
    else:
        assert gap > 1.0 and left.opening < 0.1


def test_a_recorded_mirrored_episode_is_kept_in_the_worlds_frame(library):
    """A dataset of rollouts (`realikea eval ... record=DIR`) holds what happened in the scene:
    a left-hinged door driven through the mirror records the observations and actions of the
    same motion driven without it (the policy's own are reflected), and says it was mirrored."""
    episodes, first_seen = {}, {}
    for mirrored in (False, True):
        task = _task(library, "tp_round_bar_128", "door_left_w40_h80", mirrored, RecordingTask)
        rng, first_seen[mirrored] = np.random.default_rng(0), task.reset()
        signs = mirror.ACTION_SIGNS if mirrored else 1.0
        for _ in range(task.horizon):  # the same world-frame motion, given in the policy's frame
            result = task.step(rng.uniform(-1, 1, 5) * signs)
            if result.terminated or result.truncated:
                break
        episodes[mirrored] = result.info
        assert result.info["mirrored"] is mirrored
    plain, seen = episodes[False]["steps"], episodes[True]["steps"]
    assert plain.length == seen.length > 1
    np.testing.assert_array_equal(seen.observations, plain.observations)
    np.testing.assert_array_equal(seen.actions, plain.actions)
    # the mirrored policy itself saw the reflection of what was recorded
    assert not np.array_equal(first_seen[True], seen.observations[0])
    np.testing.assert_array_equal(first_seen[True] * mirror.OBSERVATION_SIGNS, seen.observations[0])


def test_a_scripted_policy_with_the_mirror_is_refused():
    """Scripted policies plan on the scene's facts, which the mirror does not reflect."""
    with pytest.raises(RealIkeaError, match="task.mirror_doors"):
        eval_setup(["policy=heuristic_pull", "task.mirror_doors=true"])


@pytest.mark.parametrize(
    ("overrides", "mirrored"),
    [
        ([], True),
        (["task.episode_seconds=20"], True),  # another task key: the run's frame stays
        (["task.mirror_doors=false"], False),
    ],
)
def test_a_checkpoint_evaluates_in_the_frame_it_trained_in(overrides, mirrored):
    run_cfg = load_config(["task.mirror_doors=true"])
    cfg = effective_config(load_config(overrides, "eval"), run_cfg, overrides)
    assert cfg.task.mirror_doors is mirrored


def test_a_checkpoint_from_before_the_mirror_evaluates_unreflected():
    run = OmegaConf.to_container(load_config([]))
    del run["task"]["mirror_doors"]  # a run's config written before the key existed
    run_cfg = OmegaConf.create(run)
    cfg = effective_config(load_config([], "eval"), run_cfg, [])
    assert cfg.task.mirror_doors is False
