"""The rotating draw: every `every` iterations each env takes another configuration of its own
group, so a group's envs cycle through all of its configurations; groups never change; the
configuration at an iteration depends on it alone (a resumed run's envs go back where they
were); bad settings are refused before any work."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest
import torch

from realikea.assets.library import training_configurations, training_draw
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.pool.env_pool import EnvPool
from realikea.pool.rsl_rl_env import RslRlVecEnv
from realikea.training import rotating_draw
from realikea.training.rotating_draw import RotatingDraw
from realikea.training.train import check_inputs, env_groups

ROTATE = "asset.rotate_every=10"


@pytest.fixture(autouse=True)
def unbuilt(monkeypatch):
    """Moved configurations are not built (their ids stand in for the MJCFs)."""
    monkeypatch.setattr(rotating_draw, "built_models", lambda cfg, cs: [Path(c.id) for c in cs])


def rotating(*overrides, n=64):
    return RotatingDraw.from_config(load_config([ROTATE, *overrides]), n, 0)


def test_the_default_draw_does_not_rotate():
    assert load_config([]).asset.rotate_every is None
    assert not isinstance(check_inputs(load_config([])), RotatingDraw)


def test_rotation_zero_is_the_plain_draw_and_moves_wait_for_the_next_rotation():
    draw = rotating()
    plain = training_draw(load_config([]), 64, 0)
    assert draw.configurations == plain.configurations and draw.labels == plain.labels
    assert draw.moves(0) == {} and draw.moves(9) == {}
    assert draw.moves(10) and draw.moves(19) == {}


def test_each_env_keeps_its_group_and_a_group_cycles_through_all_of_its_configurations():
    draw = rotating()
    labels = list(draw.labels)
    group = ("finger_pull", "door")
    members = {c.id for c in draw.draw.groups[group]}
    envs = [i for i, label in enumerate(labels) if label == group]
    seen = Counter(draw.configurations[i].id for i in envs)
    for iteration in range(10, 10 * (len(members) // len(envs) + 1) + 1, 10):
        moved = draw.moves(iteration)
        assert all(draw.labels[i] == labels[i] for i in moved) and draw.labels == labels
        assert all(Path(moved[i]).name == draw.configurations[i].id for i in moved)
        seen.update(draw.configurations[i].id for i in envs)
    assert set(seen) == members  # every finger-pull door configuration of the train parts
    assert max(seen.values()) - min(seen.values()) <= 1  # in turns, none twice before all once
    assert draw.shares() == {"/draw/rotation": float(len(members) // len(envs) + 1)}


def test_a_resumed_run_moves_its_envs_where_the_run_left_them():
    run = rotating()
    for iteration in range(10, 71, 10):
        run.moves(iteration)
    resumed = rotating()
    resumed.moves(75)  # set_iteration on resume
    assert resumed.configurations == run.configurations


def test_env_groups_stay_those_of_the_plain_draw():
    cfg = load_config([ROTATE])
    draw = check_inputs(cfg)
    assert isinstance(draw, RotatingDraw)
    assert env_groups(draw) == env_groups(training_draw(cfg, 64, int(cfg.env.seed)))


@pytest.mark.parametrize(
    "value, match",
    [("0", "asset.rotate_every=0"), ("2.5", "asset.rotate_every=2.5"), ("true", "whole number")],
)
def test_bad_settings_are_refused_by_name(value, match):
    with pytest.raises(RealIkeaError, match=match):
        RotatingDraw.from_config(load_config([f"asset.rotate_every={value}"]), 64, 0)


def test_rotation_and_the_success_following_draw_are_refused_together():
    cfg = load_config([ROTATE, "asset.follow_success={every:50,below:0.5,weight:3}"])
    with pytest.raises(RealIkeaError, match="set one of them"):
        check_inputs(cfg)


def test_the_rsl_rl_adapter_rotates_the_pools_envs_and_logs_the_rotation(monkeypatch):
    monkeypatch.undo()  # real MJCFs for the pool
    cfg = load_config(["asset=two_point", "task.episode_seconds=1.0", "asset.rotate_every=2"])
    draw = RotatingDraw.from_config(cfg, 2, 0)
    with EnvPool(cfg, draw.paths(), num_workers=0) as pool:
        env = RslRlVecEnv(pool, cfg, num_steps_per_env=3, draw=draw)
        first = list(pool.configurations)
        for _ in range(6):  # iteration 2 at step 6: the second rotation's moves
            _, _, _, extras = env.step(torch.zeros((2, 5)))
        assert pool.configurations != first
        assert pool.configurations == training_configurations(cfg, 4, seed=0)[2:]
        assert extras["log"]["/draw/rotation"] == 1.0
