"""The in-process backend of the env pool (`num_workers=0`: debugging, tests): every env stepped
in the calling process, with the interface of `realikea.pool.processes.Processes`."""

from __future__ import annotations

from realikea.pool.env_slice import EnvSlice


class InProcess:
    """All envs stepped in the calling process, one `EnvSlice`."""

    def __init__(self, task_factory, cfg, paths, seeds, arrays, iteration: int):
        ids = list(range(len(paths)))
        self.envs = EnvSlice(task_factory, cfg, paths, seeds, ids, arrays, 0, iteration)
        self.horizons = self.envs.horizons()
        self.restarts = 0
        self.pids: list[int] = []

    def step(self) -> tuple[list[dict], list]:
        return self.envs.step(), []

    def reset(self, env_ids=None) -> None:
        self.envs.reset(env_ids)

    def facts(self, env_ids) -> dict:
        return self.envs.facts(env_ids)

    def set_iteration(self, iteration: int) -> None:
        self.envs.set_iteration(iteration)

    def reassign(self, moves: dict) -> None:
        self.envs.reassign(moves)

    def close(self) -> None:
        """Nothing to stop."""
