"""Compose the Hydra config outside `train.py` (CLI commands, tests) with clear override errors."""

from __future__ import annotations

from hydra import compose, initialize_config_dir
from hydra.core.global_hydra import GlobalHydra
from hydra.errors import HydraException
from omegaconf import DictConfig, OmegaConf
from omegaconf.errors import OmegaConfBaseException

from realikea.errors import RealIkeaError
from realikea.files import CONF_DIR


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
