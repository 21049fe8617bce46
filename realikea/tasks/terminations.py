"""The task's early endings as named predicates over the episode state; the first that holds
names the episode's termination (parameters: `realikea/conf/task/open.yaml` terminations)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Terminations:
    """When an episode ends early (realikea/conf/task/open.yaml: terminations)."""

    ik_failure_steps: int  # consecutive infeasible IK steps
    stagnation_steps: int  # consecutive steps of commanded motion without TCP motion
    stagnation_command: float  # |translation command| above this counts as commanded motion
    stagnation_motion: float  # m of TCP motion per step below this counts as no motion


def ik_infeasible(state: Any, t: Terminations, diverged: bool) -> bool:
    return state.ik_failures >= t.ik_failure_steps


def stagnation(state: Any, t: Terminations, diverged: bool) -> bool:
    return state.stagnant >= t.stagnation_steps


def physics_diverged(state: Any, t: Terminations, diverged: bool) -> bool:
    return diverged


# name -> predicate(episode state, parameters, the physics diverged this step), in priority order
TERMINATIONS: dict[str, Callable[[Any, Terminations, bool], bool]] = {
    "ik_infeasible": ik_infeasible,
    "stagnation": stagnation,
    "diverged": physics_diverged,
}
TIMEOUT = "timeout"  # the name of an episode that ran to the horizon


def termination(state: Any, t: Terminations, diverged: bool) -> str | None:
    """The name of the first predicate that holds, or None."""
    return next((name for name, holds in TERMINATIONS.items() if holds(state, t, diverged)), None)
