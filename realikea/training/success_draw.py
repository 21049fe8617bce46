"""A training draw that follows training success: groups that have not learned get more envs.

Why: which category × kind a run leaves unlearned differs by seed, so a fixed weight cannot
name it in advance (the runs behind this: `experiments/generalist/README.md`, "A draw that
follows training success"). So the weight follows the run: every `every` iterations, each group
whose training success over those iterations is below `below` (or that finished no episode)
takes `weight` turns of the stratified draw for every one of the others; envs move from the
groups that lost share to those that gained it, each to its group's next configuration, and
switch at the end of their current episode (`EnvPool.reassign`). At the start every group is
below, so the draw is the plain stratified one until some group learns. A resumed run starts
from the stratified draw again and re-weights `every` iterations later.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

from omegaconf import DictConfig

from realikea.assets.library import TrainingDraw, built_models, training_draw, turns
from realikea.config import config_number
from realikea.errors import RealIkeaError
from realikea.tasks.start_state import began_off_home

# the `asset.stratify` keys an episode's record carries under the same names
RECORD_KEYS = ("category", "kind")


class SuccessFollowingDraw:
    """The envs' groups and configurations, re-weighted every `every` iterations from the
    success of the episodes `record` was given (see the module doc)."""

    def __init__(self, cfg: DictConfig, draw: TrainingDraw, every: int, below: float, weight: int):
        missing = [k for k in draw.keys if k not in RECORD_KEYS]
        if missing or not draw.keys:
            raise RealIkeaError(
                f"asset.follow_success needs asset.stratify over {list(RECORD_KEYS)} "
                f"(got {draw.keys})"
            )
        self.cfg, self.draw = cfg, draw
        self.every, self.below, self.weight = every, below, weight
        self.labels = list(draw.labels)  # env i's group (after the moves asked for so far)
        self._window: dict[tuple, list[int]] = {}  # group -> [successes, episodes]
        self._last = None  # the iteration the window started (the first one seen: a resume's)

    @classmethod
    def from_config(cls, cfg: DictConfig, n: int, seed: int) -> SuccessFollowingDraw:
        """`cfg.asset.follow_success` ({every, below, weight}) over the draw of `n` envs."""
        follow, path = cfg.asset.follow_success, "asset.follow_success"
        if not isinstance(follow, DictConfig):
            raise RealIkeaError(f"{path}={follow!r}: use null or {{every, below, weight}}")
        every, below, weight = (
            config_number(follow, k, f"{path}.{k}", minimum=m)
            for k, m in (("every", 1), ("below", 0), ("weight", 1))
        )
        if every != int(every) or weight != int(weight) or not 0 < below <= 1:
            raise RealIkeaError(
                f"{path}: every and weight are whole numbers >= 1 and below lies in (0, 1] "
                f"(got every={every}, below={below}, weight={weight})"
            )
        return cls(cfg, training_draw(cfg, n, seed), int(every), float(below), int(weight))

    def paths(self) -> list[Path]:
        """The MJCFs of the envs' first configurations (built if missing)."""
        return built_models(self.cfg, self.draw.configurations)

    def record(self, episodes: list[dict]) -> None:
        """Count the success of the episodes that carry an outcome and started at home (not
        where a start-state curriculum began them)."""
        for e in episodes:
            if "outcome" in e and not began_off_home(e):
                label = tuple(e[k] for k in self.draw.keys)
                counts = self._window.setdefault(label, [0, 0])
                counts[0] += e["outcome"] == "success"
                counts[1] += 1

    def lagging(self) -> list[tuple]:
        """The groups below `below` in the current window (or with no episode in it)."""
        out = []
        for label in self.draw.groups:
            successes, episodes = self._window.get(label, (0, 0))
            if episodes == 0 or successes / episodes < self.below:
                out.append(label)
        return out

    def targets(self, lagging: list[tuple]) -> Counter:
        """How many envs each group gets when the `lagging` ones take `weight` turns."""
        order = turns({g: self.weight if g in lagging else 1 for g in self.draw.groups})
        return Counter(order[i % len(order)] for i in range(len(self.labels)))

    def moves(self, iteration: int) -> dict[int, Path]:
        """At every `every`-th iteration: re-weight from the window and start a new one; the
        envs that change group and the MJCFs they move to (empty otherwise)."""
        if self._last is None:
            self._last = iteration
        if iteration - self._last < self.every:
            return {}
        self._last = iteration
        target = self.targets(self.lagging())
        self._window = {}
        have = Counter(self.labels)
        freed = []  # the last envs of every group over its target
        for i in reversed(range(len(self.labels))):
            label = self.labels[i]
            if have[label] > target[label]:
                have[label] -= 1
                freed.append(i)
        moved = {}
        for label in self.draw.groups:
            while have[label] < target[label]:
                i = freed.pop()
                self.labels[i] = label
                moved[i] = self.draw.take(label)
                have[label] += 1
        paths = built_models(self.cfg, list(moved.values()))
        return dict(zip(moved, paths, strict=True))

    def shares(self) -> dict[str, float]:
        """Envs per group, as `/draw/<label>` log values."""
        have = Counter(self.labels)
        return {f"/draw/{'_'.join(label)}": float(have[label]) for label in self.draw.groups}
