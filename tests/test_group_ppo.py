"""Per-group advantage normalisation (realikea/training/group_ppo.py), on rsl-rl's own storage."""

from __future__ import annotations

from types import SimpleNamespace

import torch
from tensordict import TensorDict

from realikea.config import load_config
from realikea.training.group_ppo import GroupPPO, normalized_by_group
from realikea.training.train import GROUP_PPO, runner_config


def test_each_group_gets_mean_zero_and_unit_std():
    torch.manual_seed(0)
    advantages = torch.randn(6, 5, 1)
    advantages[:, 3:] = advantages[:, 3:] * 50 + 20  # a group with large returns
    groups = torch.tensor([0, 0, 0, 1, 1])
    out = normalized_by_group(advantages, groups)
    for g in (0, 1):
        chosen = out[:, groups == g]
        assert abs(float(chosen.mean())) < 1e-5 and abs(float(chosen.std()) - 1) < 1e-5
    # whole-batch normalisation would leave the small group near zero
    whole = (advantages - advantages.mean()) / advantages.std()
    assert float(whole[:, :3].std()) < 0.1


def test_the_library_draw_trains_in_stages_one_run_of_it_multi_task_ppo_one_category_single():
    """asset=all (python train.py's draw) selects the generalist screen's adopted pipeline and,
    for one run of it (pipeline=none), agent=multitask, round 1's group_ppo; one category, or
    agent=ppo on the command line, keeps ppo.yaml as one run."""
    assert load_config().pipeline.name == "distilled_pairs_student_mirrored"
    assert load_config(["asset=two_point"]).pipeline.name == "none"
    library = runner_config(load_config(["pipeline=none"]))
    assert library["algorithm"]["class_name"] == GROUP_PPO
    assert library["num_steps_per_env"] == 48
    assert (library["algorithm"]["schedule"], library["algorithm"]["learning_rate"]) == (
        "fixed",
        3e-4,
    )
    for overrides in (["asset=two_point", "asset.kind=drawer"], ["agent=ppo"]):
        single = runner_config(load_config(overrides))
        assert single["algorithm"]["class_name"] == "PPO" and single["num_steps_per_env"] == 24
        assert single["algorithm"]["schedule"] == "adaptive"
    cfg = load_config(["agent=ppo", "+agent.group_advantages=true"])  # the option on its own
    assert runner_config(cfg)["algorithm"]["class_name"] == GROUP_PPO


def test_group_ppo_normalises_rsl_rls_advantages_per_group_after_a_rollout():
    """GroupPPO built the way rsl-rl's runner builds it, fed a rollout in which the envs of
    group 1 earn 100 times the reward of group 0."""
    torch.manual_seed(0)
    cfg = runner_config(load_config(["agent.num_steps_per_env=8"]))  # the library draw: GroupPPO
    cfg["multi_gpu"] = None
    groups = torch.tensor([0, 0, 1, 1])
    env = SimpleNamespace(num_envs=4, num_actions=2, group_index=lambda: groups)

    def observation():
        obs = torch.randn(4, 3)
        return TensorDict({"policy": obs, "critic": obs.clone()}, batch_size=[4])

    alg = GroupPPO.construct_algorithm(observation(), env, cfg, "cpu")
    assert isinstance(alg, GroupPPO)
    for _ in range(8):
        alg.act(observation())
        rewards = torch.rand(4) * torch.tensor([1.0, 1.0, 100.0, 100.0])
        alg.process_env_step(observation(), rewards, torch.zeros(4, dtype=torch.long), {})
    alg.compute_returns(observation())
    advantages = alg.storage.advantages
    for g in (0, 1):
        chosen = advantages[:, groups == g]
        assert abs(float(chosen.mean())) < 1e-5 and abs(float(chosen.std()) - 1) < 1e-4
    assert not alg.normalize_advantage_per_mini_batch  # the option is restored


def test_the_env_numbers_the_draws_groups_and_follows_a_draw_that_moves_envs():
    from realikea.pool.rsl_rl_env import RslRlVecEnv

    pool = SimpleNamespace(num_envs=3, num_actions=2, obs_size=4, horizon=10, iteration=0)
    labels = [("knob", "door"), ("finger_pull", "drawer"), ("knob", "door")]
    env = RslRlVecEnv(pool, load_config(), 8, labels=labels)
    assert env.group_index().tolist() == [1, 0, 1]
    labels[1] = ("knob", "door")  # a success-following draw moves env 1 (in place)
    assert env.group_index().tolist() == [0, 0, 0]
    assert RslRlVecEnv(pool, load_config(), 8).group_index().tolist() == [0, 0, 0]


def test_the_log_gives_each_groups_success_and_mean_end_stage(episode_log):
    episode = {"termination": "timeout", "opening": 0.0, "category": "knob"}
    log = episode_log(
        [
            {**episode, "kind": "door", "outcome": "success", "stage": 4},
            {**episode, "kind": "door", "outcome": "fail", "stage": 2},
            {**episode, "kind": "drawer", "outcome": "fail", "stage": 1},
        ]
    )
    assert log["/success/knob_door"].tolist() == [1.0, 0.0]
    assert log["/group_stage/knob_door"].mean() == 3.0
    assert log["/group_stage/knob_drawer"].tolist() == [1.0]
