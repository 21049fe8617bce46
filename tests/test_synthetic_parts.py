"""Synthetic parts past a family's sizes and parts withheld from the draw: the size law they follow,
how the catalog resolves them, and bad settings refused before anything is written."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from realikea.assets.catalog import Catalog, Part, catalog_dir
from realikea.assets.library import training_draw
from realikea.assets.split import main_dimension
from realikea.assets.synthetic import check_spec, size_law_parts, write_synthetic
from realikea.config import load_config
from realikea.errors import RealIkeaError

# each two-point family's smallest train part: the pilot's validation parts
# (experiments/generalist/README.md, "A pilot: parts beyond a family's sizes")
SMALLEST = ["tp_round_bar_64", "tp_flat_bar_96", "tp_d_handle_96", "tp_u_handle_96", "tp_bow_128"]
TWO_POINT_FLAPS = ["asset=two_point", "asset.kind=flap"]
SYNTHETIC = "asset.synthetic={span: [0.667, 1.5], per_family: 4}"


@pytest.fixture
def catalog_root(tmp_path, monkeypatch):
    """A private copy of the catalog, so synthetic parts are written beside it."""
    root = tmp_path / "catalog"
    shutil.copytree(catalog_dir(), root, ignore=shutil.ignore_patterns("imported", "synthetic"))
    monkeypatch.setenv("REALIKEA_CATALOG", str(root))
    return root


def d_handles(*sizes: float) -> list[Part]:
    """d-handles whose projection grows 0.05 m a metre of hole spacing and whose rod is 10 mm."""
    return [
        Part(f"d{s}", "two_point", "d_handle", "wood",
             {"cc": s, "projection": 0.02 + 0.05 * s, "rod_diameter": 0.01, "bend_radius": 0.01})
        for s in sizes
    ]  # fmt: skip


def test_main_dimensions_are_log_spaced_past_both_ends_of_the_family():
    made, _ = size_law_parts(d_handles(0.096, 0.128, 0.224), (2 / 3, 1.5), 5)
    sizes = [p.dims["cc"] for p in made]
    assert sizes[0] == pytest.approx(0.064, abs=1e-5) and sizes[-1] == pytest.approx(0.336)
    assert np.allclose(np.diff(np.log(sizes)), np.log(sizes[1] / sizes[0]), atol=1e-3)


def test_other_dimensions_follow_the_family_s_straight_line_law():
    made, _ = size_law_parts(d_handles(0.096, 0.128, 0.224), (2 / 3, 1.5), 3)
    for p in made:
        assert p.dims["projection"] == pytest.approx(0.02 + 0.05 * p.dims["cc"], abs=1e-5)
        assert p.dims["rod_diameter"] == pytest.approx(0.01)
    assert all(p.id.startswith("syn_d_handle_") and p.family == "d_handle" for p in made)
    assert len({p.id for p in made}) == 3


def test_a_dimension_falling_past_the_small_end_stops_at_half_its_smallest_value():
    family = d_handles(0.2, 0.3)
    family[0].dims["projection"], family[1].dims["projection"] = 0.04, 0.12
    family[0].dims["bend_radius"] = family[1].dims["bend_radius"] = 0.006
    made, refused = size_law_parts(family, (0.5, 1.0), 2)  # the line gives -0.04 at cc 0.1
    assert not refused and made[0].dims["projection"] == pytest.approx(0.02)


def test_a_size_the_family_s_rules_refuse_is_left_out_and_named():
    family = d_handles(0.2, 0.3)
    family[0].dims["rod_diameter"], family[1].dims["rod_diameter"] = 0.008, 0.014
    made, refused = size_law_parts(family, (0.5, 1.0), 2)  # a 4 mm rod at cc 0.1
    assert [p.dims["cc"] for p in made] == [0.3]
    assert len(refused) == 1 and "rod_diameter too small" in refused[0]


def test_a_synthetic_part_takes_the_friction_of_the_family_part_nearest_its_size():
    family = d_handles(0.1, 0.2)
    family[1] = Part("d0.2", "two_point", "d_handle", "polished_metal", family[1].dims)
    (small, large), _ = size_law_parts(family, (0.9, 1.1), 2)
    assert (small.friction, large.friction) == ("wood", "polished_metal")


def test_the_catalog_resolves_a_synthetic_part_outside_its_parts_and_count(catalog_root):
    made, _ = size_law_parts(d_handles(0.096, 0.128), (2 / 3, 1.5), 2)
    write_synthetic(made, catalog_root / "synthetic")
    catalog = Catalog.load()
    assert catalog.part(made[0].id) == made[0]
    assert made[0].id not in catalog.parts and catalog.n_configurations == 83 * 13


def test_withheld_parts_leave_the_draw():
    kept = training_draw(load_config([*TWO_POINT_FLAPS, f"asset.withhold={SMALLEST}"]), 64)
    parts = {c.part.id for group in kept.groups.values() for c in group}
    assert len(parts) == 23 - len(SMALLEST) and not parts & set(SMALLEST)


@pytest.mark.parametrize(
    "withhold, says",
    [(["tp_bar_9"], "unknown part"), (["knob_round_30"], "not in the draw")],
)
def test_a_withheld_part_the_draw_does_not_hold_is_refused(withhold, says):
    with pytest.raises(RealIkeaError, match=says):
        training_draw(load_config([*TWO_POINT_FLAPS, f"asset.withhold={withhold}"]), 64)


def test_synthetic_parts_join_the_draw_on_its_bases_and_are_stored(catalog_root, capsys):
    cfg = load_config([*TWO_POINT_FLAPS, f"asset.withhold={SMALLEST}", SYNTHETIC])
    draw = training_draw(cfg, 64)
    configs = [c for group in draw.groups.values() for c in group]
    made = [c for c in configs if c.part.id.startswith("syn_")]
    # the largest flat bar's straight-line posts stand past its ends: left out, and named
    assert "syn_flat_bar_5040" in capsys.readouterr().err
    assert len(made) == 5 * 4 - 1 and {c.base.id for c in made} == {"flap_w60_h40"}
    stored = {p.name.removesuffix(".json") for p in (catalog_root / "synthetic").iterdir()}
    assert stored == {c.part.id for c in made}
    smallest = min(c.part.dims["cc"] for c in made if c.part.family == "d_handle")
    trained = [main_dimension(c.part) for c in configs if c.part.family == "d_handle"]
    assert smallest == pytest.approx(0.667 * 0.128, rel=1e-4) and min(trained) == smallest


@pytest.mark.parametrize(
    "spec, says",
    [
        ({"span": [1.2, 1.5], "per_family": 4}, "span"),
        ({"span": [0.5], "per_family": 4}, "span"),
        ({"span": [0.5, "x"], "per_family": 4}, "span"),
        ({"span": [0.5, 1.5], "per_family": 1}, "per_family"),
        ({"span": [0.5, 1.5], "per_family": True}, "per_family"),
        (3, "use null or"),
    ],
)
def test_a_bad_synthetic_setting_is_refused_before_any_part_is_written(spec, says, catalog_root):
    with pytest.raises(RealIkeaError, match=says):
        check_spec(spec)
    cfg = load_config([*TWO_POINT_FLAPS, f"asset.synthetic={spec}".replace("'", "")])
    with pytest.raises(RealIkeaError, match=says):
        training_draw(cfg, 64)
    assert not (catalog_root / "synthetic").exists()
