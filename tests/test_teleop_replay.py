"""Teleoperation keys -> actions, demonstrations recorded and replayed bit for bit, bad files."""

from __future__ import annotations

import json

import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.cli import main
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.protocol import run_episodes
from realikea.policies import teleop
from realikea.policies.demonstration import (
    Recorder,
    Session,
    load_demonstration,
    save_demonstration,
)
from realikea.policies.heuristic_pull import HeuristicPull
from realikea.policies.replay import ReplayPolicy
from realikea.policies.teleop import TeleopState, next_action, press
from realikea.pool.env_pool import EnvPool
from realikea.tasks import observations
from realikea.tasks.open_task import OpenTask

PIN = ["asset=two_point", "asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20"]
RECORDED = [*PIN, "dr=fixed", "task.episode_seconds=6", "resistance=high", "env.seed=5"]


# --- keys -> actions (pure) -------------------------------------------------------------------
def _keys(*keys, state=None):
    state = state or TeleopState()
    for k in keys:
        state = press(state, k)
    return state


def test_each_motion_key_moves_one_axis_one_unit():
    expected = {
        teleop.KEY_UP: [0, -1, 0, 0],
        teleop.KEY_DOWN: [0, 1, 0, 0],
        teleop.KEY_LEFT: [0, 0, -1, 0],
        teleop.KEY_RIGHT: [0, 0, 1, 0],
        teleop.KEY_PAGE_UP: [0, 0, 0, 1],
        teleop.KEY_PAGE_DOWN: [0, 0, 0, -1],
        teleop.KEY_HOME: [1, 0, 0, 0],
        teleop.KEY_END: [-1, 0, 0, 0],
    }
    for key, motion in expected.items():
        action, reset, _ = next_action(_keys(key))
        assert action.tolist() == [*motion, 1.0] and not reset


def test_presses_add_up_clip_and_are_used_up():
    state = _keys(teleop.KEY_UP, teleop.KEY_UP, teleop.KEY_UP, teleop.KEY_LEFT, teleop.KEY_RIGHT)
    action, _, state = next_action(state)
    assert action.tolist() == [0.0, -1.0, 0.0, 0.0, 1.0]  # three presses: full speed, clipped
    action, _, _ = next_action(state)
    assert action.tolist() == [0.0, 0.0, 0.0, 0.0, 1.0]  # nothing pressed since: no motion


def test_gripper_toggles_and_stays():
    state = _keys(teleop.KEY_ENTER)
    for _ in range(3):
        action, _, state = next_action(state)
        assert action[4] == -1.0
    action, _, _ = next_action(_keys(teleop.KEY_KP_ENTER, state=state))
    assert action[4] == 1.0


def test_reset_key_and_unknown_keys():
    _, reset, state = next_action(_keys(teleop.KEY_INSERT))
    assert reset and not next_action(state)[1]
    assert _keys(ord("A"), ord(" "), 259) == TeleopState()  # letters, Space, Backspace: ignored


def test_keyboard_collects_presses_from_the_viewer_thread():
    keyboard = teleop.Keyboard()
    for key in (teleop.KEY_PAGE_UP, teleop.KEY_ENTER):
        keyboard.on_key(key)
    action, reset = keyboard.take()
    assert action.tolist() == [0.0, 0.0, 0.0, 1.0, -1.0] and not reset


def test_teleop_without_a_display_is_a_clear_error(monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["eval", "policy=teleop", "policy.record=/tmp/never.npz"]) == 2
    assert "needs a display" in capsys.readouterr().err


# --- recording and replay ---------------------------------------------------------------------
@pytest.fixture(scope="module")
def library(tmp_path_factory):
    return tmp_path_factory.mktemp("library")


def record(library, path, episodes=2, cut_at=None):
    """Episodes of the heuristic pull on one task, recorded through the teleop's recorder."""
    overrides = [*RECORDED, f"paths.library={library}"]
    cfg = load_config(overrides, "eval")
    seed = int(cfg.env.seed)
    (mjcf,) = training_configurations(cfg, 1, seed)
    task = OpenTask(cfg, mjcf, seed)
    recorder = Recorder(task, cfg, mjcf, seed, overrides, source="heuristic_pull")
    session = Session(task, recorder)
    policy = HeuristicPull.from_config(cfg)
    policy.reset([0], [task.facts()])
    while len(recorder.finished) < episodes:
        if cut_at is not None and task.state.steps == cut_at:
            session.cut()
            cut_at = None
            policy.reset([0], [task.facts()])
            continue
        _, ended = session.step(policy.act(session.obs[None])[0])
        if ended is not None:
            policy.reset([0], [task.facts()])
    recorder.save(path)
    return recorder.demonstration()


@pytest.fixture(scope="module")
def demo_file(library, tmp_path_factory):
    path = tmp_path_factory.mktemp("demos") / "pull.npz"
    return path, record(library, path)


def test_demonstration_file_holds_what_replay_needs(demo_file):
    path, recorded = demo_file
    demo = load_demonstration(path)
    meta = demo.metadata
    assert meta["config_id"] == "tp_round_bar_128__drawer_w60_h20" and meta["seed"] == 5
    assert (
        meta["overrides"][: len(RECORDED)] == RECORDED
        and meta["config"]["resistance"]["name"] == "high"
    )
    assert len(meta["mjcf_sha256"]) == 64 and meta["source"] == "heuristic_pull"
    assert len(demo.episodes) == 2
    for got, want in zip(demo.episodes, recorded.episodes, strict=True):
        assert np.array_equal(got.actions, want.actions)
        assert got.observations.shape == (got.steps + 1, observations.SIZE)
        assert got.summary["complete"]
    assert not list(path.parent.glob(".*.tmp"))  # the atomic write left no temporary file


def _replay_config(policy, library, extra=()):
    cfg = load_config(["policy=replay", f"paths.library={library}", *extra], "eval")
    cfg = policy.configure(cfg, ["policy=replay", *extra])
    cfg.contacts.log = True
    return cfg


def test_replay_reproduces_the_recording_exactly(demo_file, library):
    path, recorded = demo_file
    policy = ReplayPolicy.from_config(load_config(["policy=replay", f"policy.path={path}"]))
    cfg = _replay_config(policy, library)  # default eval groups: normal resistance, two_phase dr
    assert cfg.resistance.name == "high" and cfg.dr.mode == "fixed" and cfg.env.seed == 5
    assert cfg.env.num_envs == 1 and cfg.episodes == 2 and cfg.task.episode_seconds == 6
    with EnvPool.from_config(cfg) as pool:
        result = run_episodes(pool, policy, int(cfg.episodes), progress=False)
    assert policy.max_deviation == 0.0  # every observation bit for bit
    for got, want in zip(result.episodes, recorded.metadata["episodes"], strict=True):
        assert got["outcome"] == want["outcome"] and got["strategy"] == want["strategy"]
        assert got["opening"] == want["opening"] and got["episode_steps"] == want["steps"]
        assert got["episode_return"] == pytest.approx(want["episode_return"], abs=1e-9)


def test_replay_through_eval_reports_outcomes_and_strategies(demo_file, library, capsys):
    path, recorded = demo_file
    assert main(["eval", "policy=replay", f"policy.path={path}", f"paths.library={library}"]) == 0
    out = capsys.readouterr()
    summary = json.loads(out.out.strip().splitlines()[-1])
    outcome = recorded.metadata["episodes"][0]["outcome"]
    assert summary["episodes"] == 2 and summary[outcome] == 1.0
    assert summary["strategies"][recorded.metadata["episodes"][0]["strategy"]] == 1.0
    assert "departs from the recording" not in out.err


def test_episodes_longer_than_the_recording_hold_still(library, tmp_path):
    path = tmp_path / "cut.npz"
    demo = record(library, path, episodes=1, cut_at=20)  # the operator ended it after 20 steps
    (episode,) = demo.episodes
    assert episode.steps == 20 and not episode.summary["complete"]
    policy = ReplayPolicy.from_config(load_config(["policy=replay", f"policy.path={path}"]))
    cfg = _replay_config(policy, library)
    with EnvPool.from_config(cfg) as pool:
        obs = pool.reset()
        policy.reset([0], pool.facts([0]))
        actions = []
        for _ in range(25):
            actions.append(policy.act(obs)[0])
            obs = pool.step(actions[-1][None])[0]
    assert np.array_equal(actions[:20], episode.actions)
    held = episode.actions[-1].copy()
    held[:4] = 0.0
    assert all(np.array_equal(a, held) for a in actions[20:])  # zero motion, gripper kept
    assert policy.max_deviation == 0.0


# --- bad demonstration files ------------------------------------------------------------------
def _replay(path, capsys):
    assert main(["eval", "policy=replay", f"policy.path={path}"]) == 2
    return capsys.readouterr().err


def test_missing_and_corrupt_files(tmp_path, capsys):
    assert "demonstration not found: /nonexistent/x.npz" in _replay("/nonexistent/x.npz", capsys)
    broken = tmp_path / "broken.npz"
    broken.write_bytes(b"not a zip file")
    assert f"{broken}: not a readable demonstration" in _replay(broken, capsys)
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    assert f"{tmp_path / 'other.npz'}: not a readable demonstration" in _replay(
        tmp_path / "other.npz", capsys
    )
    assert "needs policy.path" in _replay_no_path(capsys)


def _replay_no_path(capsys):
    assert main(["eval", "policy=replay"]) == 2
    return capsys.readouterr().err


def test_another_task_layout_is_refused(demo_file, tmp_path, capsys):
    path, _ = demo_file
    demo = load_demonstration(path)
    layout = dict(demo.metadata, observation_layout=[["tcp_pos", 3], ["gripper_width", 1]])
    save_demonstration(type(demo)(demo.episodes, layout), tmp_path / "layout.npz")
    err = _replay(tmp_path / "layout.npz", capsys)
    assert f"{tmp_path / 'layout.npz'}: recorded with observation layout" in err
    assert "'gripper_width' of size 1" in err
    actions = dict(demo.metadata, action_size=7)
    save_demonstration(type(demo)(demo.episodes, actions), tmp_path / "actions.npz")
    assert "recorded with 7-D actions" in _replay(tmp_path / "actions.npz", capsys)
    episode = demo.episodes[0]
    episode.actions = np.zeros((episode.steps, 4))
    save_demonstration(type(demo)(demo.episodes, demo.metadata), tmp_path / "shape.npz")
    with pytest.raises(RealIkeaError, match="shape.npz: episode 0 has actions"):
        load_demonstration(tmp_path / "shape.npz")


def test_a_demonstration_of_the_appendix_layout_still_loads(demo_file, tmp_path):
    """Recorded before the articulation terms: its 28-D observations, its actions replayable."""
    path, _ = demo_file
    demo = load_demonstration(path)
    appendix = observations.selector(observations.APPENDIX_LAYOUT)
    for episode in demo.episodes:
        episode.observations = episode.observations[:, appendix]
    old = dict(demo.metadata, observation_layout=[list(t) for t in observations.APPENDIX_LAYOUT])
    save_demonstration(type(demo)(demo.episodes, old), tmp_path / "old.npz")
    loaded = load_demonstration(tmp_path / "old.npz")
    assert loaded.episodes[0].observations.shape[1] == 28
    np.testing.assert_array_equal(loaded.episodes[0].actions, demo.episodes[0].actions)
