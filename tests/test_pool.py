"""The env pool: determinism, equivalence to single tasks, auto-reset, self-healing, adapters."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import numpy as np
import pytest
import torch
from gymnasium.utils.env_checker import check_env
from rsl_rl.env import VecEnv
from tensordict import TensorDict

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.pool.env_pool import EnvPool
from realikea.pool.gym_env import OpenTaskEnv
from realikea.pool.rsl_rl_env import RslRlVecEnv
from realikea.tasks import observations
from realikea.tasks.open_task import OpenTask

# two-point handles on one drawer, 1 s episodes (10 control steps)
BASE = ["asset=two_point", "asset.base=drawer_w60_h20", "task.episode_seconds=1.0"]
STEPS = 10


def config(*extra):
    return load_config([*BASE, *extra])


@pytest.fixture(scope="module")
def paths():
    return training_configurations(config("dr=fixed"), 3, seed=0)


def actions(rng, n, steps):
    return rng.uniform(-1.0, 1.0, (steps, n, 5))


def rollout(pool, acts):
    out = [pool.obs]
    rewards, dones = [], []
    for a in acts:
        obs, reward, terminated, truncated, _ = pool.step(a)
        out.append(obs)
        rewards.append(reward)
        dones.append(terminated | truncated)
    return np.array(out), np.array(rewards), np.array(dones)


def alive(pid: int) -> bool:
    """A process exists and is not a zombie."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        return False
    return state != "Z"


def test_observation_layout(paths):
    assert observations.SIZE == 40
    assert sum(n for _, n in observations.LAYOUT) == observations.SIZE
    with EnvPool(config("dr=fixed"), paths[:2], num_workers=0) as pool:
        assert pool.obs.shape == (2, observations.SIZE) and pool.obs.dtype == np.float64
        obs, reward, terminated, truncated, info = pool.step(np.zeros((2, 5)))
        assert obs.shape == (2, observations.SIZE)
        assert reward.shape == terminated.shape == truncated.shape == (2,)
        assert terminated.dtype == truncated.dtype == np.bool_
        assert set(info) == {"final_obs", "episodes"} and info["final_obs"].shape == obs.shape


def test_seeded_determinism(paths):
    """Same seed: identical trajectories, whether stepped by workers or in-process."""
    cfg = config("dr=randomized")
    acts = actions(np.random.default_rng(1), 3, STEPS + 3)  # crosses an episode boundary
    with EnvPool(cfg, paths, seed=7, num_workers=2) as a, EnvPool(cfg, paths, 7, 0) as b:
        obs_a, rew_a, done_a = rollout(a, acts)
        obs_b, rew_b, done_b = rollout(b, acts)
    np.testing.assert_array_equal(obs_a, obs_b)
    np.testing.assert_array_equal(rew_a, rew_b)
    np.testing.assert_array_equal(done_a, done_b)
    assert done_a[STEPS - 1].all()
    with EnvPool(cfg, paths, seed=8, num_workers=0) as c:
        assert not np.array_equal(c.obs, obs_a[0])  # another seed perturbs other poses


def test_pool_matches_single_tasks(paths):
    """Env i of the pool is OpenTask(configuration i, seed + i), auto-reset included."""
    cfg = config("dr=randomized")
    acts = actions(np.random.default_rng(2), 3, STEPS + 4)
    with EnvPool(cfg, paths, seed=11, num_workers=2) as pool:
        obs_p, rew_p, done_p = rollout(pool, acts)
    for i, path in enumerate(paths):
        task = OpenTask(cfg, path, seed=11 + i)
        np.testing.assert_array_equal(task.reset(), obs_p[0, i])
        for k, a in enumerate(acts[:, i]):
            r = task.step(a)
            done = r.terminated or r.truncated
            obs = task.reset() if done else r.obs
            np.testing.assert_array_equal(obs, obs_p[k + 1, i])
            assert r.reward == rew_p[k, i] and done == done_p[k, i]


def test_auto_reset(paths):
    with EnvPool(config("dr=fixed"), paths[:2], num_workers=0) as pool:
        first = pool.obs
        assert pool.horizon == STEPS
        for k in range(STEPS):
            obs, _, terminated, truncated, info = pool.step(np.zeros((2, 5)))
            if k < STEPS - 1:
                assert not (terminated | truncated).any()
        assert truncated.all() and not terminated.any()
        np.testing.assert_array_equal(obs, first)  # fixed poses: the same first observation
        assert not np.array_equal(info["final_obs"], obs)
        assert [e["env"] for e in info["episodes"]] == [0, 1]
        for e in info["episodes"]:
            assert e["termination"] == "timeout" and e["episode_steps"] == STEPS
            assert e["outcome"] in ("fail", "partial", "success")
        _, _, terminated, truncated, info = pool.step(np.zeros((2, 5)))
        assert not (terminated | truncated).any() and info["episodes"] == []


def test_vecenv_contract(paths):
    cfg = config("dr=two_phase", "dr.switch_iteration=1")
    pool = EnvPool(cfg, paths[:2], num_workers=0)
    env = RslRlVecEnv(pool, cfg, num_steps_per_env=3)
    try:
        assert isinstance(env, VecEnv)
        assert (env.num_envs, env.num_actions, env.max_episode_length) == (2, 5, STEPS)
        assert env.episode_length_buf.shape == (2,) and env.device == torch.device("cpu")
        assert env.cfg.to_dict()["dr"]["mode"] == "two_phase"
        obs = env.get_observations()
        assert isinstance(obs, TensorDict) and set(obs.keys()) == {"policy", "critic"}
        for group in ("policy", "critic"):
            assert obs[group].shape == (2, observations.SIZE)
            assert obs[group].dtype == torch.float32
        first = obs["policy"].clone()
        for k in range(STEPS):
            obs, rewards, dones, extras = env.step(torch.zeros(2, 5))
            assert rewards.shape == (2,) and rewards.dtype == torch.float32
            assert dones.shape == (2,) and extras["time_outs"].dtype == torch.bool
            assert all(key.startswith("/") for key in extras["log"])
            assert env.iteration == (k + 1) // 3 and pool.iteration == env.iteration
        assert dones.all() and extras["time_outs"].all()
        log = extras["log"]
        fractions = sum(log[f"/episode/{x}"].mean() for x in ("fail", "partial", "success"))
        assert fractions == pytest.approx(1.0) and "/episode/opening" in log
        assert log["/pool/worker_restarts"] == 0
        assert log["/termination/timeout"].tolist() == [1.0, 1.0]
        assert log["/termination/stagnation"].tolist() == [0.0, 0.0]
        assert log["/episode_reward/jerk"].tolist() == [0.0, 0.0]  # zero actions: no jerk
        assert (log["/episode_reward/approach"] > 0).all()  # towards t1 from home
        assert log["/end_stage/1"].tolist() == [1.0, 1.0]
        # past dr.switch_iteration the next episode starts from perturbed poses
        handle = observations.slices()["handle_pos"]
        assert not torch.equal(obs["policy"][:, handle], first[:, handle])
        # lengths pushed past the horizon (init_at_random_ep_len) end the episode as a time-out
        env.episode_length_buf[:] = torch.tensor([STEPS - 1, 0])
        _, _, dones, extras = env.step(torch.zeros(2, 5))
        assert dones.tolist() == [1, 0] and extras["time_outs"].tolist() == [True, False]
        assert env.episode_length_buf.tolist() == [0, 1]
    finally:
        env.close()


@pytest.mark.filterwarnings("ignore:.*infinity")  # unbounded observations are honest
def test_gymnasium_checker(paths):
    env = OpenTaskEnv(
        config("dr=randomized"), paths[0], render_mode="rgb_array", width=64, height=48
    )
    try:
        check_env(env, skip_render_check=True)
        env.reset(seed=3)
        assert env.render().shape == (48, 64, 3)
        with pytest.raises(RealIkeaError):
            env.step(np.full(5, np.nan))
    finally:
        env.close()


def test_killed_worker_is_restarted(paths):
    with EnvPool(config("dr=fixed"), paths, seed=0, num_workers=2) as pool:
        for _ in range(3):
            pool.step(np.zeros((3, 5)))
        before = pool.worker_pids
        victim = before[1]  # owns env 2 (envs split [0, 1] | [2])
        os.kill(victim, signal.SIGKILL)
        obs, reward, terminated, truncated, info = pool.step(np.zeros((3, 5)))
        assert pool.counters["worker_restarts"] == 1
        assert truncated[2] and not terminated[2] and reward[2] == 0.0
        assert [e["termination"] for e in info["episodes"]] == ["worker_crash"]
        assert info["episodes"][0]["env"] == 2 and info["episodes"][0]["episode_steps"] == 4
        assert np.all(np.isfinite(obs))
        after = pool.worker_pids
        assert after[0] == before[0] and after[1] != victim and not alive(victim)
        for _ in range(STEPS):  # training goes on
            obs, *_ = pool.step(np.zeros((3, 5)))
        assert np.all(np.isfinite(obs))
    assert not any(alive(pid) for pid in after)  # closed: no zombies


def test_hung_worker_is_restarted(paths):
    with EnvPool(config("dr=fixed"), paths[:2], num_workers=2, step_timeout=2.0) as pool:
        pool.step(np.zeros((2, 5)))
        victim = pool.worker_pids[0]
        os.kill(victim, signal.SIGSTOP)  # alive but silent
        _, _, _, truncated, info = pool.step(np.zeros((2, 5)))
        assert pool.counters["worker_restarts"] == 1 and not alive(victim)
        assert truncated.tolist() == [True, False]
        assert info["episodes"][0]["termination"] == "worker_crash"


def test_bad_actions_reset_the_env(paths):
    with EnvPool(config("dr=fixed"), paths, num_workers=0) as pool:
        pool.step(np.zeros((3, 5)))
        a = np.zeros((3, 5))
        a[0, 1], a[2, 4] = np.nan, np.inf
        obs, reward, terminated, truncated, info = pool.step(a)
        assert pool.counters["bad_action_resets"] == 2
        assert truncated.tolist() == [True, False, True] and reward[[0, 2]].tolist() == [0.0, 0.0]
        assert [(e["env"], e["termination"]) for e in info["episodes"]] == [
            (0, "bad_action"),
            (2, "bad_action"),
        ]
        assert all("outcome" not in e for e in info["episodes"])
        assert np.all(np.isfinite(obs))
        with pytest.raises(RealIkeaError, match="shape"):
            pool.step(np.zeros((2, 5)))


def test_divergence_resets_the_env(paths):
    with EnvPool(config("dr=fixed"), paths[:2], num_workers=0) as pool:
        pool._backend.envs.tasks[1].data.qvel[:] = np.nan  # a blown-up state
        obs, reward, terminated, _, info = pool.step(np.zeros((2, 5)))
        assert pool.counters["divergence_resets"] == 1
        assert terminated.tolist() == [False, True] and reward[1] == 0.0
        assert info["episodes"][0]["termination"] == "diverged"
        assert np.all(np.isfinite(obs)) and np.all(np.isfinite(reward))
        obs, *_ = pool.step(np.zeros((2, 5)))
        assert np.all(np.isfinite(obs))


def test_bad_pool_input(paths, tmp_path):
    cfg = config("dr=fixed")
    with pytest.raises(RealIkeaError, match="num_workers"):
        EnvPool(cfg, paths, num_workers=-1)
    with pytest.raises(RealIkeaError, match="at least one"):
        EnvPool(cfg, [], num_workers=0)
    with pytest.raises(RealIkeaError, match="MJCF not found"):
        EnvPool(cfg, [tmp_path / "missing.xml"], num_workers=1)
    pool = EnvPool(cfg, paths[:1], num_workers=0)
    pool.close()
    with pytest.raises(RealIkeaError, match="closed"):
        pool.step(np.zeros((1, 5)))
