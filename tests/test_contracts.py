"""The task and policy contracts (`realikea/tasks/contract.py`, `realikea/policies/contract.py`):
the package's tasks and every registered policy satisfy them, and a class missing a member does
not."""

from __future__ import annotations

import importlib

import pytest
from conftest import SMALL_RUN

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.policies.contract import Policy
from realikea.policies.registry import POLICIES
from realikea.tasks.contract import Task
from realikea.tasks.open_task import OpenTask
from realikea.tasks.recording import RecordingTask


@pytest.mark.parametrize("name", sorted(POLICIES))
def test_every_registered_policy_is_a_policy(name):
    module, cls = POLICIES[name].split(":")
    assert issubclass(getattr(importlib.import_module(module), cls), Policy)


def test_a_class_without_act_is_not_a_policy():
    class NoAct:
        @classmethod
        def from_config(cls, cfg):
            return cls()

        def reset(self, env_ids, facts):
            pass

    assert not issubclass(NoAct, Policy)


@pytest.mark.parametrize("factory", [OpenTask, RecordingTask])
def test_the_package_tasks_are_tasks(sample_library, factory):
    out, _ = sample_library
    cfg = load_config([f"paths.library={out}", *SMALL_RUN, "contacts.log=true"], "eval")
    assert isinstance(factory(cfg, training_configurations(cfg, 1, 0)[0], 0), Task)


def test_a_class_without_simulate_is_not_a_task():
    class NoSimulate:
        observation_size, action_size, episode_keys = 1, 1, ()
        horizon = iteration = 0

        def reset(self): ...
        def apply_action(self, action): ...
        def evaluate(self, ok): ...
        def step(self, action): ...
        def facts(self): ...

    assert not isinstance(NoSimulate(), Task)
