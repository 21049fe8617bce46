"""Play a recorded demonstration's actions back through the normal eval path.

`realikea eval policy=replay policy.path=demos/x.npz` runs the recording's configuration with
its seed on a one-env pool (`configure`): the asset is pinned to the recorded part and base, and
the recorded resistance, collision, gripper, contact, sim, task, dr, workflow and `env.seed`
apply unless the command line overrides that group (the strategy classifier's settings stay the
eval's, as for checkpoints). `episodes` defaults to the number of recorded episodes; episode k
of the eval plays recorded episode k (cycling when more are asked for).

An episode that runs longer than its recording (an incomplete recording, another horizon, or
physics that differ) continues with `policy.after_end`: `zero_motion` (default: no translation
or pitch, the last gripper command held) or `last_action` (the last recorded action repeated).
Each observation is compared with the recorded one: `max_deviation` holds the largest
difference, and a warning is printed once it exceeds `policy.tolerance` (the replay is then no
longer the recorded trajectory).
"""

from __future__ import annotations

import sys

import numpy as np
from omegaconf import DictConfig, OmegaConf

from realikea.config import overrides_set
from realikea.errors import RealIkeaError
from realikea.files import repo_path
from realikea.policies.demonstration import Demonstration, load_demonstration
from realikea.policies.per_env import PerEnvPolicy
from realikea.tasks.open_task import ACTION_SIZE

# groups the recording brings unless the command line overrides them (the asset always)
RECORDED_GROUPS = ("resistance", "collision", "gripper", "contact", "sim", "task", "dr", "workflow")
AFTER_END = ("zero_motion", "last_action")


class ReplayPolicy(PerEnvPolicy):
    """The recorded actions of a demonstration, episode after episode, per env."""

    name = "replay"

    def __init__(self, demo: Demonstration, path, after_end: str = "zero_motion", tol=1e-6):
        if after_end not in AFTER_END:
            raise RealIkeaError(
                f"policy.after_end={after_end!r}: use one of {', '.join(AFTER_END)}"
            )
        self.demo, self.path = demo, path
        self.after_end, self.tolerance = after_end, float(tol)
        self.episode: dict[int, int] = {}  # env -> index of its current episode (-1 before)
        self.t: dict[int, int] = {}
        self.max_deviation = 0.0
        self._warned = False

    @classmethod
    def from_config(cls, cfg: DictConfig) -> ReplayPolicy:
        """`policy.path` names the demonstration (relative paths from the repository root)."""
        if not cfg.policy.get("path"):
            raise RealIkeaError(
                "policy=replay needs policy.path=PATH.npz (a recorded demonstration)"
            )
        path = repo_path(cfg.policy.path)
        policy = cfg.policy
        return cls(
            load_demonstration(path),
            path,
            str(policy.get("after_end", "zero_motion")),
            float(policy.get("tolerance", 1e-6)),
        )

    def configure(self, cfg: DictConfig, overrides: list[str]) -> DictConfig:
        """The eval config on the recorded configuration and seed, one env (see module doc)."""
        rec = self.demo.config
        meta = self.demo.metadata
        merged = OmegaConf.to_container(cfg, resolve=True)
        for group in RECORDED_GROUPS:
            if group in rec and not overrides_set(overrides, group):
                merged[group] = OmegaConf.to_container(rec[group], resolve=True)
        merged["asset"] = {
            "category": meta.get("category", rec.asset.category),
            "part": meta["part"],
            "base": meta["base"],
            "kind": None,
        }
        if not overrides_set(overrides, "env.seed"):
            merged["env"]["seed"] = self.demo.seed
        if not overrides_set(overrides, "env.num_workers"):
            merged["env"]["num_workers"] = 0  # one env: a worker process would only add start-up
        merged["env"]["num_envs"] = 1
        if not overrides_set(overrides, "episodes"):
            merged["episodes"] = len(self.demo.episodes)
        return OmegaConf.create(merged)

    def reset(self, env_ids, facts) -> None:
        """The given envs start their next recorded episode."""
        for i, f in zip(env_ids, facts, strict=True):
            if f.config_id != self.demo.config_id:
                raise RealIkeaError(
                    f"{self.path}: recorded on {self.demo.config_id}, but env {int(i)} runs "
                    f"{f.config_id}"
                )
            i = int(i)
            self.episode[i] = self.episode.get(i, -1) + 1
            self.t[i] = 0

    def _act_one(self, i: int, obs: np.ndarray) -> np.ndarray:
        k = self.episode.get(i, 0)
        recorded = self.demo.episodes[k % len(self.demo.episodes)]
        t = self.t.get(i, 0)
        self.t[i] = t + 1
        if t < recorded.steps:
            self._compare(k, t, obs, recorded.observations[t])
            return recorded.actions[t].copy()
        if recorded.steps == 0:
            return np.zeros(ACTION_SIZE)
        last = recorded.actions[-1].copy()
        if self.after_end == "zero_motion":
            last[: ACTION_SIZE - 1] = 0.0
        return last

    def _compare(self, k: int, t: int, obs: np.ndarray, expected: np.ndarray) -> None:
        deviation = float(np.max(np.abs(np.asarray(obs) - expected)))
        self.max_deviation = max(self.max_deviation, deviation)
        if deviation > self.tolerance and not self._warned:
            self._warned = True
            print(
                f"realikea: warning: {self.path}: the replay departs from the recording at "
                f"episode {k} step {t} (|obs difference| {deviation:.2e}): the physics or the "
                "config differ from the recording's",
                file=sys.stderr,
            )
