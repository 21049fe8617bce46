"""What one run of the env pool benchmark measured (`bench_pool.json`): the report is rendered
from it alone (`bench_pool.py --render`)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import NamedTuple


class RateRow(NamedTuple):
    """One number of envs: control steps per second three ways, measured back to back."""

    envs: int
    steps: int
    best_of: int
    pool: float
    limit: float  # the physics limit: mujoco.rollout on every core
    vec: float  # gymnasium's AsyncVectorEnv
    deviation: float  # replay check: max abs difference of the rollout's state from the recording
    contacts: float  # mean ncon per env after each control step
    pool_start: float  # s
    vec_start: float  # s


class SourceCost(NamedTuple):
    """One collision source's physics cost, single thread."""

    physics_us: float  # per physics step
    contacts: float
    geoms: float  # per scene


@dataclass
class Measured:
    """Everything one run measured: the report is rendered from it alone (--render)."""

    machine: str
    versions: dict[str, str]
    load: tuple[float, float]  # load average at the start and the end
    minutes: float
    cores: int
    rows: list[RateRow]
    profile_envs: int
    profile_rate: float
    profile_limit: float
    parts: list[tuple[str, float]]  # ms per env-step by part (breakdown)
    wall_ms: float  # main process per pool step
    transfer_ms: float  # of which beyond the slowest worker's compute
    core_share: float  # of a core each worker got while stepping
    rollout_us: float  # CPU per physics step in mujoco.rollout
    decimation: int
    design_envs: int
    design_best_of: int
    design: dict[str, float]
    source_envs: int
    sources: dict[str, SourceCost]

    @classmethod
    def from_json(cls, text: str) -> Measured:
        data = json.loads(text)
        data["load"] = tuple(data["load"])
        data["rows"] = [RateRow(*row) for row in data["rows"]]
        data["parts"] = [tuple(part) for part in data["parts"]]
        data["sources"] = {k: SourceCost(*v) for k, v in data["sources"].items()}
        return cls(**data)


PHYSICS_PART = "physics: decimation x mj_step (OpenTask.simulate)"
BOOKKEEPING_PART = "pool bookkeeping (checks, shared-memory writes, episode records)"


def breakdown(seconds: dict, busy: float, env_steps: int) -> list[tuple[str, float]]:
    """ms per env-step by part of the task, and the rest of the pool's step (in-process)."""
    ms = {k: v / env_steps * 1e3 for k, v in seconds.items()}
    ms["busy"] = busy / env_steps * 1e3
    rows = [
        ("IK: mink's QP (built in place, one daqp solve) + its checks", ms["ik"]),
        ("action mapping around the IK (OpenTask.apply_action)", ms["apply"] - ms["ik"]),
        (PHYSICS_PART, ms["simulate"]),
        ("observation (OpenTask.observe, incl. at resets)", ms["observe"]),
        ("reward, terminations, info (rest of OpenTask.evaluate)", ms["evaluate"] - ms["observe"]),
        ("resets (OpenTask.reset, its observation included)", ms["reset"]),
        (
            BOOKKEEPING_PART,
            ms["busy"] - ms["apply"] - ms["simulate"] - ms["evaluate"] - ms["reset"],
        ),
    ]
    return rows
