"""Procedural part generators and the 83-part catalog (realikea/catalog/parts.csv)."""

from __future__ import annotations

import csv
import math
from collections import Counter
from functools import cache
from pathlib import Path

import numpy as np
import pytest
import trimesh
from shapely.geometry import Polygon

from realikea.assets.shapes import FAMILIES, GENERATOR_VERSION, part_mesh
from realikea.errors import RealIkeaError

CATALOG = Path(__file__).resolve().parents[1] / "realikea" / "catalog" / "parts.csv"
FRICTIONS = {"polished_metal", "brushed_metal", "plastic", "wood", "rubberized"}
MAX_EXTENTS = (0.34, 0.08, 0.045)
CC_SYSTEM = {0.064, 0.096, 0.128, 0.160, 0.192, 0.224, 0.256, 0.320}
BORE_R = (0.0033 / 2, 0.0040 / 2)


def _rows() -> list[dict[str, str]]:
    with CATALOG.open(newline="") as fh:
        return list(csv.DictReader(fh))


ROWS = _rows()
BY_ID = {r["id"]: r for r in ROWS}


def _dims(row: dict[str, str]) -> dict[str, float]:
    return {k: float(row[k]) for k in FAMILIES[row["family"]].dims}


@cache
def _mesh(part_id: str) -> trimesh.Trimesh:
    row = BY_ID[part_id]
    return part_mesh(row["family"], _dims(row))


def _bore_xs(row: dict[str, str]) -> list[float]:
    dims = _dims(row)
    return [-dims["cc"] / 2, dims["cc"] / 2] if "cc" in dims else [0.0]


# --------------------------------------------------------------------------------- catalog


def test_catalog_rows_and_balance():
    assert len(ROWS) == 83
    ids = [r["id"] for r in ROWS]
    assert len(set(ids)) == len(ids)
    assert all(i == i.lower() and " " not in i for i in ids)
    counts = Counter(r["category"] for r in ROWS)
    assert set(counts) == {"knob", "two_point", "finger_pull"}
    assert all(26 <= n <= 30 for n in counts.values()), counts
    assert {r["family"] for r in ROWS} == set(FAMILIES)


def test_catalog_values():
    header = list(ROWS[0])
    assert header[:4] == ["id", "category", "family", "friction"]
    used = {k for f in FAMILIES.values() for k in f.dims}
    assert set(header[4:]) == used
    for r in ROWS:
        fam = FAMILIES[r["family"]]
        assert r["category"] == fam.category, r["id"]
        assert r["friction"] in FRICTIONS, r["id"]
        for key in header[4:]:
            if key in fam.dims:
                value = float(r[key])
                assert 0 < value < 1, (r["id"], key)
                assert len(r[key].split(".")[-1]) <= 4, (r["id"], key)
            else:
                assert r[key] == "", (r["id"], key)
        if fam.category == "two_point":
            assert any(math.isclose(float(r["cc"]), c) for c in CC_SYSTEM), r["id"]
            assert 0.020 <= float(r["projection"]) <= 0.040, r["id"]
        if fam.category == "knob":
            size = float(r["diameter"] if "diameter" in fam.dims else r["width"])
            assert 0.013 <= size <= 0.040, r["id"]
        if fam.category == "finger_pull":
            assert 0.008 <= float(r["projection"]) <= 0.020, r["id"]


def test_families_are_documented():
    assert GENERATOR_VERSION
    for name, fam in FAMILIES.items():
        assert fam.name == name
        assert fam.category in {"knob", "two_point", "finger_pull"}
        assert fam.dims and fam.doc and "\n" not in fam.doc


# --------------------------------------------------------------------------------- meshes


@pytest.mark.parametrize("part_id", list(BY_ID))
def test_part_mesh_is_a_real_solid(part_id):
    m = _mesh(part_id)
    assert m.is_watertight and m.is_volume
    assert m.body_count == 1
    assert len(m.faces) >= 2000
    assert np.all(m.extents <= np.array(MAX_EXTENTS) + 1e-9), m.extents
    assert m.bounds[0][2] >= -1e-9
    assert m.bounds[0][2] <= 1e-9  # it sits on the mounting plane
    centre_x = (m.bounds[0][0] + m.bounds[1][0]) / 2
    assert abs(centre_x) < 1e-3


@pytest.mark.parametrize("part_id", [r["id"] for r in ROWS if r["category"] == "two_point"])
def test_two_point_handles_leave_a_finger_gap(part_id):
    m = _mesh(part_id)
    locs, _, _ = m.ray.intersects_location([[0.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]])
    assert len(locs), "no bar above the mounting point"
    gap = float(locs[:, 2].min())
    assert 0.015 <= gap <= 0.030, gap


@pytest.mark.parametrize("part_id", list(BY_ID))
def test_blind_mounting_bores(part_id):
    """The bores' open circles are interior rings just above z = 0, and they end 6-11 mm deep."""
    m = _mesh(part_id)
    section = m.section(plane_origin=[0, 0, 0.001], plane_normal=[0, 0, 1])
    to_2d = np.eye(4)
    to_2d[2, 3] = -0.001
    planar, _ = section.to_2D(to_2D=to_2d)
    rings = [
        ring
        for poly in planar.polygons_full
        for ring in poly.interiors
        if math.pi * BORE_R[0] ** 2 * 0.9 <= Polygon(ring).area <= math.pi * BORE_R[1] ** 2
    ]
    found = sorted((ring.centroid.x, ring.centroid.y) for ring in rings)
    expected = sorted((x, 0.0) for x in _bore_xs(BY_ID[part_id]))
    assert len(found) == len(expected), found
    for (fx, fy), (ex, ey) in zip(found, expected, strict=True):
        assert abs(fx - ex) < 1e-4 and abs(fy - ey) < 1e-4
    # blind: a ray up the bore (slightly off axis) meets the bore floor 6-11 mm in
    origins = [[x + 0.0003, 0.0, -0.001] for x, _ in expected]
    locs, ray_idx, _ = m.ray.intersects_location(origins, [[0.0, 0.0, 1.0]] * len(origins))
    for i in range(len(origins)):
        first = locs[ray_idx == i][:, 2].min()
        assert 0.006 <= first <= 0.0111, first


def test_knob_silhouettes():
    """A mushroom knob has an undercut; cylindrical knobs are grooved."""
    m = _mesh("knob_mushroom_30")
    row = BY_ID["knob_mushroom_30"]
    z_neck = float(row["projection"]) - float(row["head_thickness"]) - 0.003
    width = m.section(plane_origin=[0, 0, z_neck], plane_normal=[0, 0, 1]).extents[0]
    assert width < 0.5 * float(row["diameter"])
    grooved = _mesh("knob_cylindrical_20")
    radii = []
    for z in np.linspace(0.006, 0.024, 37):
        sec = grooved.section(plane_origin=[0, 0, z], plane_normal=[0, 0, 1])
        radii.append(sec.extents[0] / 2)
    assert max(radii) - min(radii) >= 0.0008


def test_finger_pull_channel_opens_downward():
    """Going up from below (+y) at the lip's inner side, a fingertip enters a channel."""
    for part_id in ("fp_edge_160", "fp_lip_50", "fp_cup_96"):
        m = _mesh(part_id)
        z = 0.5 * float(BY_ID[part_id]["projection"])
        locs, _, _ = m.ray.intersects_location([[0.0, -0.1, z]], [[0.0, 1.0, 0.0]])
        assert len(locs), part_id
        first_y = locs[:, 1].min()
        assert first_y > -0.01, (part_id, first_y)  # reaches up into the channel/hollow


# --------------------------------------------------------------------------------- errors


def test_part_mesh_errors_clearly():
    with pytest.raises(RealIkeaError, match="unknown part family 'banana'"):
        part_mesh("banana", {})
    dims = _dims(BY_ID["tp_round_bar_128"])
    missing = dict(dims)
    del missing["cc"]
    with pytest.raises(RealIkeaError, match="missing dimension 'cc'"):
        part_mesh("round_bar", missing)
    with pytest.raises(RealIkeaError, match="positive"):
        part_mesh("round_bar", dict(dims, bar_diameter=-0.01))
    with pytest.raises(RealIkeaError, match="projection"):
        part_mesh("round_bar", dict(dims, bar_diameter=0.05))
    with pytest.raises(RealIkeaError, match="projection"):
        part_mesh("d_handle", {**_dims(BY_ID["tp_d_handle_96"]), "projection": 0.008})
