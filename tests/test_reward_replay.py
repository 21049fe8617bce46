"""The task's numbers do not drift: a recorded episode replayed action by action gives the same
observations, rewards and ending.

`tests/data/reference_episode.npz` was recorded (commit 3fa6ac1's task code, before the task
became named terms) by running `hook_oracle` with Gaussian action noise (sigma 0.3, seed 0, so
the jerk and IK terms are exercised) for one episode of the configuration its `overrides` name,
under MuJoCo 3.x. MuJoCo 4.0.0 (2026-11-06) replays it to round-off: rewards within 7e-13
relative (1.2e-11 absolute; the return 5798.3896387627 against ...24), observations within
9e-13, the same stage, outcome and ending. So floats are compared to 1e-9 relative, three orders
above the engine's round-off and far below what a changed reward term, weight or control step
moves (whole units), and the discrete ending exactly.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.tasks import observations
from realikea.tasks.observations import APPENDIX_LAYOUT
from realikea.tasks.open_task import OpenTask

REFERENCE = Path(__file__).parent / "data" / "reference_episode.npz"
ROUND_OFF = 1e-9  # relative: the engine's round-off across MuJoCo releases is 1e-12 (docstring)


def test_replayed_episode_gives_the_recorded_rewards_to_round_off(tmp_path):
    ref = np.load(REFERENCE)
    # recorded with the appendix reward (latched) and its w_open2 = 0
    overrides = [*ref["overrides"].tolist(), "task/reward=appendix", "task.reward.w_open2=0.0"]
    cfg = load_config([*overrides, f"paths.library={tmp_path}"])
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    recorded_obs = [task.reset()]
    rewards, result = [], None
    for action in ref["actions"]:
        result = task.step(action)
        rewards.append(result.reward)
        recorded_obs.append(result.obs)
    assert result.terminated or result.truncated
    np.testing.assert_allclose(np.array(rewards), ref["rewards"], rtol=ROUND_OFF, atol=0)
    # recorded before the articulation terms: the appendix's terms of today's vector
    appendix = observations.selector(APPENDIX_LAYOUT)
    np.testing.assert_allclose(
        np.array(recorded_obs)[:, appendix], ref["observations"], rtol=ROUND_OFF, atol=ROUND_OFF
    )
    recorded = json.loads(str(ref["info"]))
    # the episode's return and length are counted by the env pool now, not by the task
    assert sum(rewards) == pytest.approx(recorded.pop("episode_return"), rel=ROUND_OFF, abs=0)
    assert len(rewards) == recorded.pop("episode_steps")
    opening = recorded.pop("opening")
    assert result.info["opening"] == pytest.approx(opening, rel=ROUND_OFF, abs=0)
    assert {k: result.info[k] for k in recorded} == recorded
