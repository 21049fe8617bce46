"""The fidelity grid v2 (experiments/fidelity_ablation/grid_v2.py): the runs it plans, and every
run composing to the frozen recipe, so a later change of the defaults cannot change them."""

from __future__ import annotations

from collections import Counter

import pytest
from omegaconf import OmegaConf

from realikea.config import load_config


@pytest.fixture(scope="module")
def grid_v2(load_script):
    return load_script("experiments/fidelity_ablation/grid_v2.py")


def test_the_grid_plans_66_runs_on_fresh_seeds_five_a_side_in_the_compared_cells(grid_v2):
    runs = grid_v2.planned()
    assert len(runs) == 66 and len({r.name for r in runs}) == 66
    seeds = Counter((r.category, r.resistance, r.collision) for r in runs)
    for (category, resistance, _), n in seeds.items():
        assert n == (5 if (category, resistance) in grid_v2.FIVE_SEED_CELLS else 3)
    assert {r.seed for r in runs} == set(range(100, 105))
    assert runs[0].seed == 100 and runs[-1].seed == 104  # every cell's first seed first


def test_a_run_trains_on_drawers_of_train_parts_in_the_kitchen_and_is_evaluated_on_test_parts(
    grid_v2,
):
    if not grid_v2.RECIPE.is_file():
        pytest.skip("the recipe is frozen after the pilot (grid_v2.py --freeze)")
    cfg = load_config(list(grid_v2.planned()[0].overrides))
    assert (cfg.asset.kind, cfg.asset.split, cfg.scene.name) == ("drawer", "train", "kitchen")
    assert (cfg.dr.mode, cfg.dr.switch_iteration, cfg.agent.max_iterations) == (
        "two_phase",
        300,
        600,
    )
    assert cfg.env.num_envs == 64 and cfg.env.seed == 100
    spec = cfg.train.eval_after
    assert (spec.split, spec.collision, spec.episodes, spec.dr) == (
        "test",
        "coacd",
        50,
        "randomized",
    )


def test_every_run_composes_to_the_frozen_recipe(grid_v2):
    if not grid_v2.RECIPE.is_file():
        pytest.skip("the recipe is frozen after the pilot (grid_v2.py --freeze)")
    frozen = grid_v2.frozen_recipe()
    for run in grid_v2.planned():
        assert grid_v2.recipe_of(load_config(list(run.overrides))) == frozen, run.name


def test_freezing_twice_is_refused(grid_v2, tmp_path, monkeypatch):
    monkeypatch.setattr(grid_v2, "RECIPE", tmp_path / "recipe.yaml")
    grid_v2.freeze()
    assert OmegaConf.load(tmp_path / "recipe.yaml").agent.max_iterations == 600
    with pytest.raises(SystemExit, match="the recipe is frozen"):
        grid_v2.freeze()
