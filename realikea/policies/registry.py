"""The policies `realikea eval policy=NAME` can run, built from the composed config."""

from __future__ import annotations

import importlib

from omegaconf import DictConfig

from realikea.errors import RealIkeaError
from realikea.policies.contract import Policy

# name -> "module:class" of a `Policy` (realikea/policies/contract.py)
POLICIES = {
    "checkpoint": "realikea.policies.checkpoint:CheckpointPolicy",
    "heuristic_pull": "realikea.policies.heuristic_pull:HeuristicPull",
    "grasp_sampler": "realikea.policies.grasp_sampler:GraspSampler",
    "hook_oracle": "realikea.policies.hook_oracle:HookOracle",
    "teleop": "realikea.policies.teleop:TeleopPolicy",
    "replay": "realikea.policies.replay:ReplayPolicy",
}


def make_policy(cfg: DictConfig) -> Policy:
    """The policy named by `cfg.policy.name`."""
    name = cfg.policy.name
    if name not in POLICIES:
        raise RealIkeaError(f"unknown policy {name!r}; use one of {', '.join(POLICIES)}")
    module, cls = POLICIES[name].split(":")
    return getattr(importlib.import_module(module), cls).from_config(cfg)
