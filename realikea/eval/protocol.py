"""Run a policy for N episodes on the env pool and report Fail / Partial / Success."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np
from tqdm import tqdm

from realikea.markdown import table
from realikea.pool.env_pool import EnvPool
from realikea.tasks.contacts import STRATEGIES
from realikea.tasks.failure_modes import FAILURE_MODES
from realikea.tasks.outcome import OUTCOMES, fractions


@dataclass
class EvalResult:
    """Finished episodes (one dict each, as the pool reports them) and their summary."""

    episodes: list[dict]

    @property
    def outcomes(self) -> list[str]:
        return [e.get("outcome", "fail") for e in self.episodes]

    def summary(self) -> dict:
        """`{"episodes", "fail", "partial", "success", "strategies", "success_strategies",
        "failure_modes", "policy_notes"}`: the JSON line of an eval.

        `strategies` holds the fraction of episodes per classifier label,
        `success_strategies` the fraction of the successful episodes per label (all zero without
        a success) and `failure_modes` the fraction of all episodes that failed (fail or
        partial) in each mode (they add up to 1 - success); all three only when contacts were
        logged. `policy_notes` counts the episodes per
        reason a scripted policy gave for not moving (`WaypointPolicy.note`), only if any.
        """
        out = {"episodes": len(self.episodes), **fractions(self.outcomes)}
        labelled = [e for e in self.episodes if "strategy" in e]
        if labelled:
            labels = [e["strategy"] for e in labelled]
            out["strategies"] = {s: labels.count(s) / len(labels) for s in STRATEGIES}
            won = [e["strategy"] for e in labelled if e.get("outcome") == "success"]
            out["success_strategies"] = {s: won.count(s) / max(len(won), 1) for s in STRATEGIES}
            modes = [e.get("failure_mode") for e in labelled]
            out["failure_modes"] = {m: modes.count(m) / len(labelled) for m in FAILURE_MODES}
        notes = Counter(e["policy_note"] for e in self.episodes if "policy_note" in e)
        if notes:
            out["policy_notes"] = dict(sorted(notes.items()))
        return out


def episode_quotas(episodes: int, num_envs: int) -> np.ndarray:
    """Episodes each env contributes: as equal as possible, the first envs one more."""
    quotas = np.full(num_envs, episodes // num_envs)
    quotas[: episodes % num_envs] += 1
    return quotas


def run_episodes(pool: EnvPool, policy, episodes: int, progress: bool = True) -> EvalResult:
    """Step every env until each has finished its quota of episodes (`episode_quotas`).

    Quotas keep every configuration equally represented: counting episodes in the order they
    finish would over-sample the envs whose episodes end early (usually failures).
    """
    quotas = episode_quotas(episodes, pool.num_envs)
    counts = np.zeros(pool.num_envs, dtype=int)
    finished: list[dict] = []
    obs = pool.reset()
    everyone = np.arange(pool.num_envs)
    policy.reset(everyone, pool.facts(everyone))
    with tqdm(total=episodes, desc="episodes", disable=not progress) as bar:
        while len(finished) < episodes:
            obs, _, terminated, truncated, info = pool.step(policy.act(obs))
            done = np.flatnonzero(terminated | truncated)
            notes = dict(getattr(policy, "note", {}))  # of the episodes that just ended
            if len(done):
                policy.reset(done, pool.facts(done))
            for e in info["episodes"]:
                env = e["env"]
                if e.get("termination") != "worker_crash" and counts[env] < quotas[env]:
                    if env in notes:
                        e["policy_note"] = notes[env]
                    counts[env] += 1
                    finished.append(e)
                    bar.update(1)
    return EvalResult(finished)


def outcome_table(result: EvalResult) -> str:
    """A one-line markdown table of the outcome fractions."""
    f = result.summary()
    row = [str(f["episodes"]), *(f"{f[o]:.2f}" for o in OUTCOMES)]
    return "\n".join(table(["episodes", *OUTCOMES], "l" * (1 + len(OUTCOMES)), [row]))
