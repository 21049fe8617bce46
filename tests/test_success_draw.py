"""The draw that follows training success: lagging groups gain envs, envs switch configuration
at their next episode, bad settings are refused before any work."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import numpy as np
import pytest
import torch

from realikea.assets.library import training_configurations, training_draw
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.pool.env_pool import RESEED, EnvPool
from realikea.pool.rsl_rl_env import RslRlVecEnv
from realikea.tasks.open_task import OpenTask
from realikea.training import success_draw
from realikea.training.success_draw import SuccessFollowingDraw

FOLLOW = "asset.follow_success={every:10,below:0.5,weight:3}"


@pytest.fixture
def draw(monkeypatch):
    """64 envs of the default draw; moved configurations are not built (their ids stand in)."""
    monkeypatch.setattr(success_draw, "built_models", lambda cfg, cs: [Path(c.id) for c in cs])
    return SuccessFollowingDraw.from_config(load_config([FOLLOW]), 64, 0)


def episodes(label, successes, failures):
    category, kind = label
    ends = ["success"] * successes + ["fail"] * failures
    return [{"outcome": o, "category": category, "kind": kind} for o in ends]


def test_the_default_draw_does_not_follow_success():
    assert load_config([]).asset.follow_success is None


def test_a_group_below_the_bar_gains_envs_from_the_learned_ones(draw):
    groups = list(draw.draw.groups)
    lagging = groups[4]
    for label in groups:
        draw.record(episodes(label, *((1, 9) if label == lagging else (9, 1))))
    assert draw.moves(0) == {}  # the first iteration seen starts the window
    assert draw.moves(9) == {}
    before = list(draw.labels)
    moved = draw.moves(10)
    have = Counter(draw.labels)
    # 9 groups, the lagging one with three turns: 5 rounds of 11 turns, then one of each group
    assert have[lagging] == 16 and sum(have.values()) == 64
    assert all(have[g] == 6 for g in groups if g != lagging)
    assert set(moved) == {i for i in range(64) if draw.labels[i] != before[i]}
    assert all(draw.labels[i] == lagging for i in moved)
    assert all(Path(p).name in {c.id for c in draw.draw.groups[lagging]} for p in moved.values())
    ids = [Path(p).name for p in moved.values()]
    assert len(set(ids)) == len(ids)  # each move takes the group's next configuration


def test_when_every_group_lags_the_draw_stays_the_stratified_one(draw):
    start = list(draw.labels)
    draw.moves(0)
    draw.record(episodes(next(iter(draw.draw.groups)), 0, 5))  # one group measured, all below
    assert draw.moves(10) == {} and draw.labels == start
    assert draw.labels == training_draw(load_config([]), 64, 0).labels


def test_a_group_that_learns_gives_its_envs_back(draw):
    groups = list(draw.draw.groups)
    draw.moves(0)
    for label in groups:
        draw.record(episodes(label, *((0, 10) if label == groups[0] else (10, 0))))
    draw.moves(10)
    assert Counter(draw.labels)[groups[0]] == 16
    for label in groups:
        draw.record(episodes(label, 10, 0))
    draw.moves(20)
    plain = Counter(training_draw(load_config([]), 64, 0).labels)
    assert Counter(draw.labels) == plain
    assert draw.shares()[f"/draw/{'_'.join(groups[0])}"] == plain[groups[0]]


@pytest.mark.parametrize(
    "value, match",
    [
        ("3", "asset.follow_success=3"),
        ("{every:0,below:0.5,weight:3}", "asset.follow_success.every"),
        ("{every:50,below:1.5,weight:3}", "below lies in"),
        ("{every:50,below:0.5,weight:1.5}", "whole numbers"),
        ("{every:50,below:0.5}", "asset.follow_success.weight"),
    ],
)
def test_bad_settings_are_refused_by_name(value, match):
    cfg = load_config([f"asset.follow_success={value}"])
    with pytest.raises(RealIkeaError, match=match):
        SuccessFollowingDraw.from_config(cfg, 64, 0)


def test_a_draw_without_category_and_kind_groups_is_refused():
    cfg = load_config(["asset=knob", f"+{FOLLOW}"])
    with pytest.raises(RealIkeaError, match="asset.stratify"):
        SuccessFollowingDraw.from_config(cfg, 8, 0)


# --- the pool's side: an env switches configuration at its next episode --------------------
# three configurations on three bases (two doors, a drawer), randomized poses: the first
# observation tells both the configuration and the seed
BASE = ["asset=two_point", "task.episode_seconds=1.0", "dr=randomized"]
STEPS = 10


@pytest.mark.parametrize("workers", [0, 2])
def test_a_reassigned_env_runs_its_new_configuration_from_its_next_episode(workers):
    cfg = load_config(BASE)
    paths = training_configurations(cfg, 3, seed=0)
    with EnvPool(cfg, paths[:2], seed=5, num_workers=workers) as pool:
        pool.reassign({0: paths[2]})
        zero = np.zeros((2, 5))
        for _ in range(STEPS - 1):  # the current episode runs on
            obs, *_ = pool.step(zero)
        before = OpenTask(cfg, paths[0], seed=5)
        before.reset()
        for _ in range(STEPS - 1):
            expected = before.step(zero[0]).obs
        np.testing.assert_array_equal(obs[0], expected)
        obs, *_, info = pool.step(zero)  # the episode ends: the next starts on paths[2]
        assert [e["env"] for e in info["episodes"]] == [0, 1]
        after = OpenTask(cfg, paths[2], seed=5 + 0 + 2 * (RESEED + 1))
        np.testing.assert_array_equal(obs[0], after.reset())
        assert pool.configurations[0] == paths[2] and pool.configurations[1] == paths[1]


def test_a_bad_reassignment_is_refused_before_any_work(tmp_path):
    cfg = load_config(BASE)
    paths = training_configurations(cfg, 1, seed=0)
    with EnvPool(cfg, paths, num_workers=0) as pool:
        with pytest.raises(RealIkeaError, match="env ids"):
            pool.reassign({3: paths[0]})
        with pytest.raises(RealIkeaError, match="missing.xml"):
            pool.reassign({0: tmp_path / "missing.xml"})
        assert pool.configurations == paths


class OneMove:
    """A draw that moves env 1 to `path` at iteration 2 and records what it was fed."""

    def __init__(self, path):
        self.path, self.fed = path, []

    def record(self, episodes):
        self.fed += episodes

    def moves(self, iteration):
        return {1: self.path} if iteration == 2 else {}

    def shares(self):
        return {"/draw/x": 1.0}


def test_the_rsl_rl_adapter_feeds_the_draw_and_hands_its_moves_to_the_pool():
    cfg = load_config(BASE)
    paths = training_configurations(cfg, 3, seed=0)
    draw = OneMove(paths[2])
    with EnvPool(cfg, paths[:2], num_workers=0) as pool:
        env = RslRlVecEnv(pool, cfg, num_steps_per_env=3, draw=draw)
        for _ in range(STEPS):
            _, _, _, extras = env.step(torch.zeros((2, 5)))
        assert pool.configurations == [paths[0], paths[2]]
        assert len(draw.fed) == 2 and extras["log"]["/draw/x"] == 1.0
