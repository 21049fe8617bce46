"""The task's numbers do not drift: a recorded episode replayed action by action gives the same
observations, rewards and ending, bit for bit.

`tests/data/reference_episode.npz` was recorded (commit 3fa6ac1's task code, before the task
became named terms) by running `hook_oracle` with Gaussian action noise (sigma 0.3, seed 0, so
the jerk and IK terms are exercised) for one episode of the configuration its `overrides` name.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.tasks import observations
from realikea.tasks.observations import APPENDIX_LAYOUT
from realikea.tasks.open_task import OpenTask

REFERENCE = Path(__file__).parent / "data" / "reference_episode.npz"


def test_replayed_episode_gives_the_recorded_rewards_bit_for_bit(tmp_path):
    ref = np.load(REFERENCE)
    # recorded with the appendix's w_open2 = 0 (the default since is 2.0: realikea/conf/task)
    overrides = [*ref["overrides"].tolist(), "task.reward.w_open2=0.0"]
    cfg = load_config([*overrides, f"paths.library={tmp_path}"])
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    recorded_obs = [task.reset()]
    rewards, result = [], None
    for action in ref["actions"]:
        result = task.step(action)
        rewards.append(result.reward)
        recorded_obs.append(result.obs)
    assert result.terminated or result.truncated
    np.testing.assert_array_equal(np.array(rewards), ref["rewards"])
    # recorded before the articulation terms: the appendix's terms of today's vector
    appendix = observations.selector(APPENDIX_LAYOUT)
    np.testing.assert_array_equal(np.array(recorded_obs)[:, appendix], ref["observations"])
    recorded = json.loads(str(ref["info"]))
    # the episode's return and length are counted by the env pool now, not by the task
    assert sum(rewards) == recorded.pop("episode_return")
    assert len(rewards) == recorded.pop("episode_steps")
    assert {k: result.info[k] for k in recorded} == recorded
