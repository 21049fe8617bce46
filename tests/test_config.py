"""Hydra groups compose, and unknown values fail with the options named."""

from __future__ import annotations

import pytest

from realikea.cli import main
from realikea.config import load_config
from realikea.errors import RealIkeaError


@pytest.mark.parametrize(
    ("mode", "damping", "friction"), [("smooth", 2, 5), ("normal", 5, 10), ("high", 10, 20)]
)
def test_resistance_modes_match_the_paper(mode, damping, friction):
    cfg = load_config([f"resistance={mode}"])
    assert (cfg.resistance.damping, cfg.resistance.frictionloss) == (damping, friction)


def test_asset_group_and_pinning():
    cfg = load_config(["asset=knob", "asset.part=some_part", "asset.base=drawer_w60_h20"])
    assert (cfg.asset.category, cfg.asset.part, cfg.asset.base) == (
        "knob",
        "some_part",
        "drawer_w60_h20",
    )
    assert load_config(["collision=hull"]).collision.source == "hull"


@pytest.mark.parametrize("override", ["resistance=extreme", "collision=mesh", "asset=chair"])
def test_unknown_group_value_names_the_options(override):
    with pytest.raises(RealIkeaError, match="Available options") as err:
        load_config([override])
    assert override.split("=")[1] in str(err.value)


def test_unknown_key_is_an_error():
    with pytest.raises(RealIkeaError, match="nonsense"):
        load_config(["nonsense=1"])


def test_cli_reports_bad_override_without_traceback(capsys):
    assert main(["assets", "build", "--part", "x", "collision=extreme"]) == 2
    err = capsys.readouterr().err
    assert "collision/extreme" in err and "Traceback" not in err


def test_train_py_composes_the_config(train_py_job):
    assert "source: hull" in train_py_job and "frictionloss: 20.0" in train_py_job


def test_evaluation_keeps_its_32_env_draw_whatever_trainings_default():
    """Training's default pool is 64 envs (the generalist); evaluation spreads its episodes over
    32, the draw every committed table was made with."""
    assert load_config([]).env.num_envs == 64
    assert load_config([], "eval").env.num_envs == 32
    assert load_config(["env.num_envs=8"], "eval").env.num_envs == 8


def test_asset_all_draws_by_turns_over_category_and_kind():
    assert list(load_config([]).asset.stratify) == ["category", "kind"]
    assert load_config(["asset=knob"]).asset.stratify is None
