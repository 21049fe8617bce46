"""One episode, step by step: reset once, every step's result, the steered action taken."""

from types import SimpleNamespace

import numpy as np

from realikea.policies.rollout import episode, final_info


class _Task:
    """Truncates after `horizon` steps; remembers the actions it was given."""

    def __init__(self, horizon: int):
        self.horizon, self.steps, self.actions, self.resets = horizon, 0, [], 0

    def reset(self):
        self.resets += 1
        return np.zeros(2)

    def facts(self):
        return "facts"

    def step(self, action):
        self.steps += 1
        self.actions.append(action.copy())
        done = self.steps >= self.horizon
        return SimpleNamespace(obs=np.zeros(2), terminated=False, truncated=done,
                               info={"step": self.steps})  # fmt: skip


class _Policy:
    def reset(self, env_ids, facts):
        self.reset_with = (list(env_ids), facts)

    def act(self, obs):
        return np.ones((len(obs), 3))


def test_an_episode_yields_each_step_and_ends_at_truncation():
    task, policy = _Task(4), _Policy()
    results = list(episode(task, policy))
    assert [r.info["step"] for r in results] == [1, 2, 3, 4]
    assert task.resets == 1 and policy.reset_with == ([0], ["facts"])
    assert final_info(_Task(2), _Policy()) == {"step": 2}


def test_steer_changes_the_action_from_its_step_on():
    task = _Task(3)

    def steer(t, action):
        return action * 2 if t >= 1 else action

    list(episode(task, _Policy(), steer))
    assert [a.tolist() for a in task.actions] == [[1, 1, 1], [2, 2, 2], [2, 2, 2]]
