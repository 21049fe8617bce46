"""The env pool as rsl-rl's `VecEnv`: TensorDict observations, time-outs, episode outcome logs.

Both observation groups, `policy` (actor) and `critic`, hold the privileged observation. The
training iteration is env steps // num_steps_per_env (the runner collects that many steps per
iteration); when it changes the pool hears of it, so the two-phase randomization switches at
`cfg.dr.switch_iteration`. After resuming from a checkpoint call `set_iteration(it)`.

With a `draw` (`realikea/training/success_draw.py`, `rotating_draw.py`) the adapter feeds it
every finished episode and, at each new iteration (and on resuming), hands the pool the envs it
moves (`EnvPool.reassign`); the draw's `shares()` are logged (`/draw/<group>`, `/draw/rotation`).
"""

from __future__ import annotations

import math

import numpy as np
import torch
from omegaconf import DictConfig, OmegaConf
from rsl_rl.env import VecEnv
from tensordict import TensorDict

from realikea.assets.catalog import group_name
from realikea.errors import RealIkeaError
from realikea.pool.env_pool import EnvPool
from realikea.rewards import STAGES
from realikea.tasks.outcome import OUTCOMES
from realikea.tasks.start_state import STARTS, began_off_home
from realikea.tasks.terminations import TERMINATIONS, TIMEOUT

OBS_GROUPS = ("policy", "critic")


class EnvConfig(dict):
    """The resolved config as a dict with `to_dict()` (what rsl-rl's log writers store)."""

    def to_dict(self) -> dict:
        return dict(self)


class RslRlVecEnv(VecEnv):
    """rsl-rl's view of an `EnvPool`; `close()` closes the pool."""

    def __init__(
        self,
        pool: EnvPool,
        cfg: DictConfig,
        num_steps_per_env: int,
        device: str = "cpu",
        draw=None,
        labels: list[tuple] | None = None,
        groups: list[str] | None = None,
    ):
        if int(num_steps_per_env) < 1:
            raise RealIkeaError(f"num_steps_per_env={num_steps_per_env}: use 1 or more")
        self.pool = pool
        self.cfg = EnvConfig(OmegaConf.to_container(cfg, resolve=True))
        self.num_steps_per_env = int(num_steps_per_env)
        self.num_envs = pool.num_envs
        self.num_actions = pool.num_actions
        self.num_obs = pool.obs_size
        self.max_episode_length = int(pool.horizon)
        self.device = torch.device(device)
        self.episode_length_buf = torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
        self.common_step_counter = 0
        self.iteration = pool.iteration
        self.draw = draw
        self.labels = labels if labels is not None else []  # env i's group; a draw updates it
        self.groups = groups or []  # env i's category x kind group name (distillation routes on it)

    def group_index(self) -> torch.Tensor:
        """Each env's task group as an index (its label's place among the sorted labels); all 0
        without labels (a draw not stratified)."""
        if not self.labels:
            return torch.zeros(self.num_envs, dtype=torch.long, device=self.device)
        order = {label: i for i, label in enumerate(sorted(set(self.labels)))}
        return torch.tensor([order[x] for x in self.labels], device=self.device)

    # --- iteration ----------------------------------------------------------------------------
    def set_iteration(self, iteration: int) -> None:
        """Continue counting from a training iteration (resume)."""
        self.common_step_counter = int(iteration) * self.num_steps_per_env
        self.iteration = int(iteration)
        self.pool.set_iteration(self.iteration)
        if self.draw is not None and (moves := self.draw.moves(self.iteration)):
            self.pool.reassign(moves)  # a rotating draw's envs, back where the run left them

    # --- VecEnv -------------------------------------------------------------------------------
    def _observations(self, obs: np.ndarray) -> TensorDict:
        policy = torch.as_tensor(obs, dtype=torch.float32, device=self.device)
        return TensorDict(
            {"policy": policy, "critic": policy.clone()},
            batch_size=[self.num_envs],
            device=self.device,
        )

    def get_observations(self) -> TensorDict:
        return self._observations(self.pool.obs)

    def step(self, actions: torch.Tensor) -> tuple[TensorDict, torch.Tensor, torch.Tensor, dict]:
        a = actions.detach().to("cpu", torch.float64).numpy()
        obs, reward, terminated, truncated, info = self.pool.step(a)
        self.common_step_counter += 1
        iteration = self.common_step_counter // self.num_steps_per_env
        if self.draw is not None:
            self.draw.record(info["episodes"])
        if iteration != self.iteration:
            self.iteration = iteration
            self.pool.set_iteration(iteration)
            if self.draw is not None and (moves := self.draw.moves(iteration)):
                self.pool.reassign(moves)

        done = torch.as_tensor(terminated | truncated, device=self.device)
        self.episode_length_buf += 1
        self.episode_length_buf[done] = 0
        # lengths pushed past the horizon from outside (the runner's init_at_random_ep_len)
        over = (self.episode_length_buf >= self.max_episode_length).cpu().numpy()
        if over.any():
            ids = np.flatnonzero(over)
            obs = self.pool.reset(ids)
            truncated = truncated.copy()
            truncated[ids] = True
            self.episode_length_buf[torch.as_tensor(ids)] = 0

        dones = torch.as_tensor(terminated | truncated, dtype=torch.long, device=self.device)
        extras = {
            "time_outs": torch.as_tensor(truncated, device=self.device),
            "log": self._log(info["episodes"]),
        }
        rewards = torch.as_tensor(reward, dtype=torch.float32, device=self.device)
        return self._observations(obs), rewards, dones, extras

    def _log(self, episodes: list[dict]) -> dict[str, float | torch.Tensor]:
        """Per-episode values (rsl-rl averages them over the iteration): outcome indicators, each
        reward term's episode sum (`/episode_reward/<term>`), the reward stage an episode ended
        in (`/end_stage/<1-4>`), termination indicators
        (`/termination/<name>`), success and the mean end stage per category and kind
        (`/success/<category>_<kind>`, `/group_stage/<category>_<kind>`, over the iteration's
        episodes of that group: a group stuck before the pull shows as a low stage); and the
        pool's counters. Outcomes and group values count the episodes that started at home, the
        task as evaluated; those a start-state curriculum began elsewhere show as
        `/pregrasp_success/<category>_<kind>` or `/ajar_success/<category>_<kind>`. A finger-pull
        group's success also shows over its episodes on parts whose channel the pad enters
        (`/pad_enters_success/finger_pull_<kind>`, `realikea.tasks.open_task.pad_enters`)."""
        log: dict[str, float | torch.Tensor] = {}
        if episodes:
            names = [e["termination"] for e in episodes]
            for name in dict.fromkeys([*TERMINATIONS, TIMEOUT, *names]):
                log[f"/termination/{name}"] = torch.tensor([float(x == name) for x in names])
        summed = [e["reward_terms"] for e in episodes if "reward_terms" in e]
        for term in dict.fromkeys(t for terms in summed for t in terms):
            log[f"/episode_reward/{term}"] = torch.tensor([e.get(term, 0.0) for e in summed])
        stages = [int(e["stage"]) for e in episodes if "stage" in e]
        for stage in range(1, STAGES + 1) if stages else ():
            log[f"/end_stage/{stage}"] = torch.tensor([float(x == stage) for x in stages])
        curricula: dict[str, list[float]] = {}
        for e in episodes:
            for flag in STARTS:
                if e.get(flag):
                    group = group_name(e["category"], e["kind"])
                    curricula.setdefault(f"/{flag}_success/{group}", []).append(
                        float(e["outcome"] == "success")
                    )
        log.update({name: torch.tensor(values) for name, values in sorted(curricula.items())})
        finished = [e for e in episodes if "outcome" in e and not began_off_home(e)]
        if finished:
            labels = [e["outcome"] for e in finished]
            for name in OUTCOMES:
                log[f"/episode/{name}"] = torch.tensor([float(x == name) for x in labels])
            openings = [e["opening"] for e in finished if math.isfinite(e["opening"])]
            if openings:
                log["/episode/opening"] = torch.tensor(openings, dtype=torch.float32)
            groups: dict[str, list[float]] = {}
            for e in finished:
                if "category" in e:
                    group = group_name(e["category"], e["kind"])
                    groups.setdefault(f"/success/{group}", []).append(
                        float(e["outcome"] == "success")
                    )
                    if "stage" in e:
                        groups.setdefault(f"/group_stage/{group}", []).append(float(e["stage"]))
                    if e["category"] == "finger_pull" and e.get("pad_enters"):
                        groups.setdefault(f"/pad_enters_success/{group}", []).append(
                            float(e["outcome"] == "success")
                        )
            log.update({name: torch.tensor(values) for name, values in sorted(groups.items())})
        for name, value in self.pool.counters.items():
            log[f"/pool/{name}"] = float(value)
        if self.draw is not None:
            log.update(self.draw.shares())
        return log

    def close(self) -> None:
        self.pool.close()
