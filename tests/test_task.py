"""The opening task on one scene: layout, determinism, bad actions, randomization."""

from __future__ import annotations

import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.rewards import VARIANTS
from realikea.tasks import observations
from realikea.tasks.open_task import OpenTask

PIN = ["asset=two_point", "asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20"]


@pytest.fixture(scope="module")
def drawer(tmp_path_factory):
    """A built two-point-handle drawer and the config to simulate it."""
    library = tmp_path_factory.mktemp("library")
    cfg = load_config([*PIN, "dr=fixed", f"paths.library={library}"])
    (mjcf,) = training_configurations(cfg, 1)
    return cfg, mjcf


def _rollout(task: OpenTask, steps: int, seed: int):
    rng = np.random.default_rng(seed)
    obs = [task.reset()]
    rewards = []
    for _ in range(steps):
        result = task.step(rng.uniform(-1, 1, 5))
        obs.append(result.obs)
        rewards.append(result.reward)
    return np.array(obs), np.array(rewards)


def test_observation_layout(drawer):
    cfg, mjcf = drawer
    task = OpenTask(cfg, mjcf)
    obs = task.reset()
    assert obs.shape == (observations.SIZE,) == (40,)
    s = observations.slices()
    assert obs[s["stage"]].tolist() == [1, 0, 0, 0]
    assert obs[s["joint_type"]].tolist() == [1.0, 0.0]  # a drawer slides
    assert obs[s["category"]].tolist() == [0.0, 1.0, 0.0]  # two_point
    # a drawer's handle moves towards the robot (+x) along the slide, and has not moved yet
    np.testing.assert_allclose(obs[s["pull_dir"]], obs[s["joint_axis"]], atol=1e-9)
    assert obs[s["pull_dir"]][0] > 0.99 and obs[s["progress"]][0] == 0.0
    assert obs[s["opening"]][0] == 0.0 and obs[s["aperture"]][0] == pytest.approx(1.0)
    assert task.horizon == 120 and task.joint_type == "slide"


def test_same_seed_same_trajectory(drawer):
    cfg, mjcf = drawer
    a = _rollout(OpenTask(cfg, mjcf, seed=3), 15, seed=7)
    b = _rollout(OpenTask(cfg, mjcf, seed=3), 15, seed=7)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


@pytest.mark.parametrize("action", [[np.nan, 0, 0, 0, 0], [0, np.inf, 0, 0, 0], [0, 0, 0, 0]])
def test_bad_actions_are_refused(drawer, action):
    cfg, mjcf = drawer
    task = OpenTask(cfg, mjcf)
    task.reset()
    with pytest.raises(RealIkeaError, match="action must be 5 finite numbers"):
        task.step(np.array(action, dtype=float))


def test_randomization_moves_handle_only_when_active(drawer):
    cfg, mjcf = drawer
    task = OpenTask(load_config([*PIN, "dr=two_phase", f"paths.library={mjcf.parents[1]}"]), mjcf)
    handles = []
    for iteration in (0, 0, 900, 900):
        task.iteration = iteration
        obs = task.reset()
        handles.append(obs[observations.slices()["handle_pos"]])
    assert np.allclose(handles[0], handles[1])  # phase one: fixed poses
    assert not np.allclose(handles[2], handles[3])  # phase two: perturbed per episode
    assert np.all(np.abs(handles[2] - handles[0]) < 0.1)


def test_commanded_motion_moves_the_tcp(drawer):
    cfg, mjcf = drawer
    task = OpenTask(cfg, mjcf)
    obs = task.reset()
    tcp = observations.slices()["tcp_pos"]
    for _ in range(10):
        result = task.step(np.array([0.0, 0.0, 0.0, 1.0, 1.0]))  # up 1 cm per step
    assert result.obs[tcp][2] - obs[tcp][2] == pytest.approx(0.10, abs=0.02)
    assert result.info["ik_ok"]


def test_observation_terms_have_their_declared_sizes():
    v = observations.ObservationInputs(
        [0.1, 0.2, 0.3], np.eye(3).tolist(), [0.4, 0.5, 0.6], [0.0, 0.0, 0.0],
        0.01, 0.0, 0.5, False, [0.0] * 5, 2, True, [0, 0, 1.0], [1.0, 0, 0], 0.1, 2,
    )  # fmt: skip
    for name, size, term in observations.TERMS:
        assert len(term(v)) == size, name
    assert observations.observation(v).shape == (observations.SIZE,)


def test_reward_terms_sum_to_the_episode_return(drawer):
    cfg, mjcf = drawer
    task = OpenTask(cfg, mjcf, seed=1)
    task.reset()
    rng = np.random.default_rng(0)
    result = task.step(rng.uniform(-1, 1, 5))
    rewards = [result.reward]
    while not (result.terminated or result.truncated):
        result = task.step(rng.uniform(-1, 1, 5))
        rewards.append(result.reward)
    terms = result.info["reward_terms"]
    assert set(terms) == set(VARIANTS[cfg.task.reward.variant].terms)
    assert sum(terms.values()) == pytest.approx(sum(rewards))
    assert terms["jerk"] < 0  # random actions are jerky
