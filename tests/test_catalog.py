"""Catalog integrity: 83 parts, 13 bases, 1,079 configurations, unique ids, clear errors."""

from __future__ import annotations

import shutil
from collections import Counter

import pytest

from realikea.assets.catalog import CATEGORIES, Catalog, catalog_dir
from realikea.errors import RealIkeaError


def test_counts(catalog):
    assert len(catalog.parts) == 83
    assert len(catalog.bases) == 13
    assert catalog.n_configurations == 1079
    assert len(list(catalog.configurations())) == 1079
    assert len({c.id for c in catalog.configurations()}) == 1079


def test_categories_roughly_balanced(catalog):
    counts = Counter(p.category for p in catalog.parts.values())
    assert set(counts) == set(CATEGORIES)
    assert max(counts.values()) - min(counts.values()) <= 3


def test_bases_cover_every_joint_mechanism(catalog):
    bases = catalog.bases.values()
    kinds = Counter((b.kind, b.hinge) for b in bases)
    assert kinds[("door", "left")] >= 1 and kinds[("door", "right")] >= 1
    assert kinds[("flap", "bottom")] >= 1
    drawers = [b for b in bases if b.kind == "drawer"]
    assert len({b.height for b in drawers}) >= 3 and len({b.width for b in drawers}) >= 3
    assert all(b.joint == ("slide" if b.kind == "drawer" else "hinge") for b in bases)


def test_category_filter_and_pinning(catalog):
    knobs = list(catalog.configurations("knob"))
    assert {c.part.category for c in knobs} == {"knob"}
    assert len(knobs) == 13 * len(catalog.parts_in("knob"))
    part = catalog.parts_in("two_point")[0].id
    pinned = list(catalog.configurations(part=part, base="flap_w60_h40"))
    assert [c.id for c in pinned] == [f"{part}__flap_w60_h40"]


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda c: c.part("no_such_part"), "unknown part id 'no_such_part'"),
        (lambda c: c.base("garage_door"), "unknown base id 'garage_door'"),
        (lambda c: c.parts_in("lever"), "unknown category 'lever'"),
    ],
)
def test_unknown_ids_name_the_input(catalog, call, message):
    with pytest.raises(RealIkeaError, match=message):
        call(catalog)


def _catalog_copy(tmp_path):
    root = tmp_path / "catalog"
    shutil.copytree(catalog_dir(), root)
    return root


def test_bad_rows_name_the_file_and_row(tmp_path):
    root = _catalog_copy(tmp_path)
    bases = (root / "bases.csv").read_text().replace("drawer,slide", "drawer,hinge", 1)
    (root / "bases.csv").write_text(bases)
    with pytest.raises(RealIkeaError, match=r"bases\.csv: drawer_w40_h20: kind 'drawer'"):
        Catalog.load(root)


def test_non_numeric_dimension_is_an_error(tmp_path):
    root = _catalog_copy(tmp_path)
    lines = (root / "parts.csv").read_text().splitlines()
    header = lines[0].split(",")
    row = lines[1].split(",")
    column = next(i for i in range(4, len(row)) if row[i])
    row[column] = "12mm"
    (root / "parts.csv").write_text("\n".join([lines[0], ",".join(row), *lines[2:]]) + "\n")
    with pytest.raises(RealIkeaError, match=f"{row[0]}: column '{header[column]}' is not a number"):
        Catalog.load(root)


def test_duplicate_part_id_is_an_error(tmp_path):
    root = _catalog_copy(tmp_path)
    lines = (root / "parts.csv").read_text().splitlines()
    (root / "parts.csv").write_text("\n".join([*lines, lines[1]]) + "\n")
    with pytest.raises(RealIkeaError, match="duplicate part id"):
        Catalog.load(root)


def test_kind_filter(catalog):
    drawers = list(catalog.configurations("two_point", kind="drawer"))
    assert {c.base.kind for c in drawers} == {"drawer"}
    assert len(drawers) == len(catalog.parts_in("two_point")) * 8
    with pytest.raises(RealIkeaError, match="unknown base kind 'wardrobe'"):
        list(catalog.configurations(kind="wardrobe"))


def test_unknown_ids_suggest_close_matches_and_list_the_valid_ones(catalog):
    with pytest.raises(RealIkeaError) as err:
        catalog.part("knob_rund_20")
    message = " ".join(str(err.value).split())  # the list is wrapped over lines
    assert "unknown part id 'knob_rund_20'; did you mean knob_round_20" in message
    assert f"known part ids (83): {', '.join(sorted(catalog.parts))}" in message
    with pytest.raises(RealIkeaError) as err:
        catalog.base("drawer_w60_h2")
    message = " ".join(str(err.value).split())
    assert "did you mean drawer_w60_h20" in message
    assert f"known base ids (13): {', '.join(sorted(catalog.bases))}" in message
    with pytest.raises(RealIkeaError) as err:  # nothing close: the list alone
        list(catalog.configurations(part="zzz"))
    assert "did you mean" not in str(err.value) and "known part ids (83)" in str(err.value)
