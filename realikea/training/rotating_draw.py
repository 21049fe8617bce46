"""A training draw whose envs take turns over their group's configurations.

Why: the plain draw gives each env one configuration for the whole run, so with 64 envs over
the library's nine category x kind groups a group trains on about 7 of its configurations, and
the seed decides which. Finger-pull doors have 76 train configurations; seed 20's seven hold
four on parts the committed generalists open in 1 of their 42 validation episodes
(`experiments/generalist/README.md`, "Which finger pulls open"). Here every `every` iterations
each env moves to another configuration of its own group (`EnvPool.reassign`: at the end of its
current episode), so over a run every group's envs cycle through all of its configurations.

The groups never change (an env keeps its category x kind, which multi-task PPO's per-group
advantages read). Rotation r gives the j-th env of a group of n envs its group's member
(j + r * n) mod (members), in the draw's seeded order: rotation 0 is the plain draw, and the
configuration at an iteration depends on the iteration alone, so a resumed run moves its envs
to where the run left them.
"""

from __future__ import annotations

from pathlib import Path

from omegaconf import DictConfig

from realikea.assets.library import TrainingDraw, built_models, training_draw
from realikea.errors import RealIkeaError


class RotatingDraw:
    """The envs' configurations, moved to their group's next ones every `every` iterations."""

    def __init__(self, cfg: DictConfig, draw: TrainingDraw, every: int):
        self.cfg, self.draw, self.every = cfg, draw, every
        self.labels = list(draw.labels)
        self.configurations = list(draw.configurations)
        self._rank = []  # env i is the _rank[i]-th env of its group
        seen: dict[tuple, int] = {}
        for label in self.labels:
            self._rank.append(seen.get(label, 0))
            seen[label] = self._rank[-1] + 1
        self._size = seen  # envs per group
        self._rotation = 0

    @classmethod
    def from_config(cls, cfg: DictConfig, n: int, seed: int) -> RotatingDraw:
        """`cfg.asset.rotate_every` (whole iterations >= 1) over the draw of `n` envs."""
        every = cfg.asset.rotate_every
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            raise RealIkeaError(
                f"asset.rotate_every={every!r}: use null or a whole number of iterations >= 1"
            )
        if cfg.asset.get("follow_success") is not None:
            raise RealIkeaError(
                "asset.rotate_every and asset.follow_success both move envs: set one of them"
            )
        return cls(cfg, training_draw(cfg, n, seed), every)

    def member(self, i: int, rotation: int) -> int:
        """Env i's index into its group's members at `rotation`."""
        label = self.labels[i]
        return (self._rank[i] + rotation * self._size[label]) % len(self.draw.groups[label])

    def paths(self) -> list[Path]:
        """The MJCFs of the envs' first configurations (built if missing)."""
        return built_models(self.cfg, self.configurations)

    def record(self, episodes: list[dict]) -> None:
        """Nothing: the rotation follows the iteration alone."""

    def moves(self, iteration: int) -> dict[int, Path]:
        """At a new rotation (every `every` iterations): the envs whose configuration changes
        and the MJCFs they move to (empty otherwise)."""
        rotation = iteration // self.every
        if rotation == self._rotation:
            return {}
        self._rotation = rotation
        moved = {}
        for i, label in enumerate(self.labels):
            configuration = self.draw.groups[label][self.member(i, rotation)]
            if configuration != self.configurations[i]:
                self.configurations[i] = moved[i] = configuration
        paths = built_models(self.cfg, list(moved.values()))
        return dict(zip(moved, paths, strict=True))

    def shares(self) -> dict[str, float]:
        """The rotation reached, as a `/draw/rotation` log value (the groups never change)."""
        return {"/draw/rotation": float(self._rotation)}
