"""Compose the Hydra config outside `train.py` (CLI commands, tests) with clear override errors."""

from __future__ import annotations

from hydra import compose, initialize_config_dir
from hydra.core.global_hydra import GlobalHydra
from hydra.errors import HydraException
from omegaconf import DictConfig, OmegaConf
from omegaconf.errors import OmegaConfBaseException

from realikea.errors import RealIkeaError
from realikea.files import CONF_DIR
from realikea.rewards import store_configs


def config_number(node: DictConfig, key: str, path: str, minimum: float | None = None) -> float:
    """A numeric config value, or an error naming the key and the bad value."""
    value = node.get(key)
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise RealIkeaError(f"config value {path}={value!r} is not a number") from None
    if minimum is not None and number < minimum:
        raise RealIkeaError(f"config value {path}={value!r} must be >= {minimum:g}")
    return number


# numeric settings and their lowest allowed value: counts (integers) and intervals; a key a config
# does not have, or a null where null means "the default" (env.num_workers), is not checked
INTEGER_MINIMA = {
    "agent.max_iterations": 1,
    "agent.num_steps_per_env": 1,
    "agent.save_interval": 1,
    "agent.algorithm.num_learning_epochs": 1,
    "agent.algorithm.num_mini_batches": 1,
    "env.num_envs": 1,
    "env.num_workers": 0,
    "dr.switch_iteration": 0,
    "train.torch_threads": 1,
    "train.eval_after.episodes": 1,
    "episodes": 1,
    "video_episodes": 0,
}
POSITIVE = ("env.step_timeout", "agent.algorithm.learning_rate")  # real numbers above zero


def check_settings(cfg: DictConfig) -> None:
    """Refuse, naming the key, a count below its minimum, a non-integer count or a non-positive
    interval: before any work, so a bad setting never trains nothing and exits 0."""
    for key, minimum in INTEGER_MINIMA.items():
        value = OmegaConf.select(cfg, key, default=None)
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            raise RealIkeaError(f"{key}={value!r}: use an integer >= {minimum}")
    for key in POSITIVE:
        value = OmegaConf.select(cfg, key, default=None)
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
            raise RealIkeaError(f"{key}={value!r}: use a number > 0")


def override_key(override: str) -> str:
    """The key a Hydra override sets: `+a.b=1` -> `a.b`, `~a` -> `a`, `group=x` -> `group`."""
    return override.lstrip("+~").split("=", 1)[0]


def overrides_set(overrides, key: str) -> bool:
    """Whether any override sets `key` itself or a key under it (`asset` covers `asset.kind`)."""
    return any(k == key or k.startswith(key + ".") for k in map(override_key, overrides))


def load_config(overrides: list[str] | tuple[str, ...] = (), name: str = "config") -> DictConfig:
    """A primary config (`config`: the shared one; `eval`: evaluation's) with Hydra-style
    `group=value` / `key=value` overrides applied."""
    GlobalHydra.instance().clear()
    store_configs()
    try:
        with initialize_config_dir(str(CONF_DIR), version_base="1.3"):
            cfg = compose(name, overrides=list(overrides))
        OmegaConf.resolve(cfg)
    except (HydraException, OmegaConfBaseException) as err:
        message = str(err).split("\nConfig search path")[0].strip()
        raise RealIkeaError(f"bad config override {' '.join(overrides)!r}: {message}") from err
    finally:
        GlobalHydra.instance().clear()
    return cfg
