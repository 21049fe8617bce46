"""What a fingertip can catch, read off a part's mesh (realikea/assets/catch_geometry.py).

Reference: the catalog's dimension rows, through the formulas in `_catalog_reference` that
read a catch off them. Every catalog part is
compared on the generator's mesh (`part_mesh`, the build's visual.obj with the screw bores
open; `test_built_visual_mesh_gives_the_same_features` checks the bores make no difference).

Tolerance `TOL` = 0.5 mm: the scan lines are 0.1 mm apart, and the generators round every
edge a hand meets (lip corners 0.45 x thickness, knob rims up to 1.5 mm), which the dimension
rows do not know; 0.5 mm is also a quarter of the plan's 2 mm clearance. Where the catalog
formula was itself an approximation of the solid, the test says so and compares what the solid
implies:

* square knobs: the catalog puts the head's back rim at the underside's sharp corner; the head's
  bottom edge is rounded with `edge_radius` e, so the profile reaches full radius (within
  `FULL_RADIUS_TOL`) e - sqrt(e^2 - (e - tol)^2) higher (0.7-2.8 mm on the catalog).
* tapered (trumpet) knobs: the catalog's back rim `proj - 1.5 mm - 2.2 e` ignores the fillet of
  radius 0.18 x projection between the flare and the rim; compared within 1 mm.
* cups: the catalog assumed the hollow stops at the 2 mm flange and put the roof at the screw
  ears (y = 0); in the solid the hollow cuts through the flange down to the front (back = 0)
  and its roof at x = 0 rises to the inner shell's apex, height / 2 - thickness.
* cylindrical knobs (grooves 0.6-1.5 mm deep) and straight cones offer no undercut: NoCatch,
  where the catalog formula wedged against the face's rim.
"""

from __future__ import annotations

import math
from dataclasses import asdict
from functools import cache

import numpy as np
import pytest
import trimesh

from realikea.assets.catalog import Catalog
from realikea.assets.catch_geometry import (
    FULL_RADIUS_TOL,
    MIN_ROOM,
    BarCatch,
    KnobCatch,
    LipCatch,
    NoCatch,
    catch_features,
    catch_features_at,
)
from realikea.assets.shapes import part_mesh
from realikea.assets.workflow import cleaning, segmentation
from realikea.eval.protocol import EvalResult
from realikea.policies.hook_oracle import HookOracle
from realikea.policies.scripted import OPEN
from realikea.sim.ik import NOMINAL_TCP_ROTATION
from realikea.tasks.facts import SceneFacts

TOL = 5e-4  # m, see the module docstring
TAPERED_TOL = 1e-3  # m, the catalog's tapered back rim is a rough formula
_ROOF_MIN = 0.0064  # m: what the old policy knew of the finger pulls' generator

PARTS = Catalog.load().parts


def _catalog_reference(d: dict, category: str) -> dict:
    """hook_oracle's former `_feature`: the catchable geometry from the catalog's dimensions."""
    proj = d["projection"]
    if category == "two_point":
        height = next(
            d[k] for k in ("bar_diameter", "bar_width", "rod_diameter", "strap_width") if k in d
        )
        depth = next(
            d[k]
            for k in ("bar_diameter", "bar_thickness", "rod_diameter", "strap_thickness")
            if k in d
        )
        return {"proj": proj, "height": height, "depth": depth}
    if category == "knob":
        radius = d.get("diameter", d.get("width", 0.0)) / 2
        if "head_thickness" in d:  # a head on a neck: the head's back face
            back, neck = proj - d["head_thickness"], d["neck_diameter"] / 2
        elif "edge_radius" in d and "base_diameter" in d:  # tapered: the rim behind the face
            back, neck = proj - 0.0015 - 2.2 * d["edge_radius"], d["base_diameter"] / 2
        else:  # cylindrical: no undercut; the face's rounded rim is all there is
            back, neck = proj - max(0.0025, 1.5 * min(0.002, 0.2 * radius)), radius
        return {"radius": radius, "back": back, "neck": min(neck, radius)}
    t = d["thickness"]
    if "lip_drop" in d:
        roof = max(_ROOF_MIN, t)
        edge_y = roof / 2 - roof - d["lip_drop"]
        return {"edge_y": edge_y, "edge_z": proj - t, "back": t, "top": roof / 2 - roof}
    return {"edge_y": -d["height"] / 2, "edge_z": proj - t, "back": 0.002, "top": 0.0}


def _expected(part) -> tuple[dict, dict[str, float]]:
    """(values, tolerances) the mesh should give: the catalog reference, corrected where the
    catalog formula misread the solid (module docstring)."""
    d = part.dims
    ref = _catalog_reference(d, part.category)
    tol = dict.fromkeys(ref, TOL)
    if part.family == "square":
        e, r = d["edge_radius"], FULL_RADIUS_TOL
        ref["back"] += e - math.sqrt(e**2 - (e - r) ** 2)
    elif part.family == "tapered":
        tol["back"] = TAPERED_TOL
    elif part.family == "cup":
        ref["back"], ref["top"] = 0.0, d["height"] / 2 - d["thickness"]
    return ref, tol


def _no_undercut(part) -> bool:
    d = part.dims
    return part.family == "cylindrical" or (
        part.family == "tapered" and d["base_diameter"] >= d["diameter"]
    )


@cache
def _mesh(part_id: str) -> trimesh.Trimesh:
    part = PARTS[part_id]
    return part_mesh(part.family, part.dims)


CATALOG_IDS = sorted(p.id for p in PARTS.values() if p.mesh_file is None)


def test_catalog_parts_agree_with_their_dimensions():
    """All 83 catalog parts: the mesh gives what the dimensions imply (or NoCatch without an
    undercut), each family's worst disagreement within its tolerance."""
    assert len(CATALOG_IDS) == 83
    kinds = {"two_point": BarCatch, "knob": KnobCatch, "finger_pull": LipCatch}
    problems = []
    for pid in CATALOG_IDS:
        part = PARTS[pid]
        found = catch_features(_mesh(pid), part.category)
        if _no_undercut(part):
            if not (isinstance(found, NoCatch) and "undercut" in found.reason):
                problems.append((pid, "expected NoCatch (no undercut)", found))
            continue
        if not isinstance(found, kinds[part.category]):
            problems.append((pid, f"expected {kinds[part.category].__name__}", found))
            continue
        ref, tol = _expected(part)
        got = asdict(found)
        for key, value in ref.items():
            if abs(got[key] - value) > tol[key]:
                problems.append((pid, key, round(got[key] * 1e3, 2), round(value * 1e3, 2)))
    assert not problems, problems


def test_no_undercut_reasons_name_the_undercut():
    found = catch_features(_mesh("knob_cylindrical_13"), "knob")
    assert found == NoCatch("no undercut behind the knob's head (0.6 mm < 2.0 mm)")
    cone = catch_features(_mesh("knob_tapered_18_cone"), "knob")
    assert isinstance(cone, NoCatch) and "(0.0 mm < 2.0 mm)" in cone.reason


def test_built_visual_mesh_gives_the_same_features(tmp_path):
    """The build's visual.obj (steps 1-2: bores filled, re-meshed) reads like `part_mesh`, one
    part per family, through the cached file loader."""
    families = {}
    for pid in CATALOG_IDS:
        families.setdefault(PARTS[pid].family, pid)
    for pid in families.values():
        part = PARTS[pid]
        solid = cleaning.cleaned_solid(segmentation.formatted_components(part))
        path = tmp_path / f"{pid}.obj"
        solid.export(path)
        built = catch_features_at(str(path), part.category)
        direct = catch_features(_mesh(pid), part.category)
        assert type(built) is type(direct), pid
        if isinstance(direct, NoCatch):
            continue
        for key, value in asdict(direct).items():
            assert asdict(built)[key] == pytest.approx(value, abs=1e-6), (pid, key)
    assert catch_features_at(str(path), part.category) is built  # cached by path


# --------------------------------------------------------------------------------- imported


def _part_frame(mesh_mm: trimesh.Trimesh) -> trimesh.Trimesh:
    """A CAD export in millimetres as `realikea assets import --scale 0.001` brings it in."""
    mesh = mesh_mm.copy()
    mesh.apply_scale(0.001)
    lo, hi = mesh.bounds
    mesh.apply_translation([-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]])
    return mesh


def _cylinder(radius, height, axis, centre, sections=64):
    c = trimesh.creation.cylinder(radius=radius, height=height, sections=sections)
    if axis == "x":
        c.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    c.apply_translation(centre)
    return c


def test_imported_two_point_handle_in_millimetres():
    """A bar (12 mm round, top 31 mm out) on two posts, drawn in mm: a gap of 19 mm behind."""
    bar = _cylinder(6, 128, "x", [0, 0, 25])
    posts = [_cylinder(5, 25, "z", [x, 0, 12.5]) for x in (-48, 48)]
    mesh = _part_frame(trimesh.boolean.union([bar, *posts], engine="manifold"))
    found = catch_features(mesh, "two_point")
    assert isinstance(found, BarCatch)
    assert found.proj == pytest.approx(0.031, abs=1e-4)
    assert found.height == pytest.approx(0.012, abs=1e-4)
    assert found.depth == pytest.approx(0.012, abs=1e-4)


def test_imported_mushroom_knob_in_millimetres():
    """test_import's scanned knob: a 6 mm neck under a 30 mm domed head (an ellipsoid)."""
    neck = _cylinder(6, 14, "z", [0, 0, 7])
    head = trimesh.creation.icosphere(subdivisions=4, radius=15)
    head.apply_scale([1, 1, 0.5])
    head.apply_translation([0, 0, 20])
    mesh = _part_frame(trimesh.boolean.union([neck, head], engine="manifold"))
    found = catch_features(mesh, "knob")
    assert isinstance(found, KnobCatch)
    assert found.radius == pytest.approx(0.015, abs=3e-4)  # the icosphere's facets
    assert found.neck == pytest.approx(0.006, abs=3e-4)
    # the ellipsoid (equator at z = 20 mm, half-height 7.5 mm) is within 0.5 mm of its
    # equator's radius from 1.9 mm below the equator up
    assert 0.020 - 0.0025 < found.back < 0.020


@pytest.mark.parametrize(
    ("category", "reason"),
    [
        ("two_point", "no gap behind the bar"),
        ("knob", "no undercut behind the knob's head"),
        ("finger_pull", "no channel behind a lip"),
    ],
)
def test_a_plain_block_offers_nothing_to_catch(category, reason):
    mesh = trimesh.creation.box(extents=[0.1, 0.02, 0.015])
    mesh.apply_translation([0, 0, 0.0075])
    found = catch_features(mesh, category)
    assert isinstance(found, NoCatch) and reason in found.reason, found


def test_a_shallow_channel_is_too_small_for_a_fingertip():
    """A lip hanging 1.5 mm below its roof: under the 2 mm a fingertip needs."""
    plate = trimesh.creation.box(extents=[60, 20, 2])
    plate.apply_translation([0, 0, 1])
    roof = trimesh.creation.box(extents=[60, 6, 12])
    roof.apply_translation([0, 7, 6])
    lip = trimesh.creation.box(extents=[60, 7.5, 2])
    lip.apply_translation([0, 6.25, 11])
    mesh = _part_frame(trimesh.boolean.union([plate, roof, lip], engine="manifold"))
    found = catch_features(mesh, "finger_pull")
    assert isinstance(found, NoCatch) and "1.5 mm" in found.reason, found
    assert MIN_ROOM == 0.002


# --------------------------------------------------------------------------------- the oracle


def _facts(tmp_path, part_id: str) -> SceneFacts:
    """A drawer part facing +x (part z), y up: the hand's nominal approach goes into the front."""
    part = PARTS[part_id]
    path = tmp_path / f"{part_id}.obj"
    _mesh(part_id).export(path)
    rot = np.column_stack([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    return SceneFacts(
        config_id=f"{part_id}__drawer",
        part_id=part_id,
        category=part.category,
        base_kind="drawer",
        joint_type="slide",
        robot_base=np.zeros(3),
        handle_pos=np.array([0.6, 0.0, 0.5]),
        part_pos=np.array([0.6, 0.0, 0.5]),
        part_rot=rot,
        pull_dir=np.array([1.0, 0.0, 0.0]),
        hinge_anchor=None,
        hinge_axis=None,
        visual_mesh=str(path),
        tcp_nominal=NOMINAL_TCP_ROTATION,
    )


def test_oracle_holds_still_with_a_reason_when_nothing_can_be_caught(tmp_path, capsys):
    oracle = HookOracle()
    facts = [_facts(tmp_path, "knob_cylindrical_13"), _facts(tmp_path, "knob_round_20")]
    oracle.reset(np.array([0, 1]), facts)
    oracle.reset(np.array([0]), facts[:1])  # a second episode: one warning per reason
    assert oracle.plans[0] == [] and oracle.plans[1]
    assert oracle.note == {
        0: "knob_cylindrical_13: no undercut behind the knob's head (0.6 mm < 2.0 mm)"
    }
    assert capsys.readouterr().err.count("warning: hook_oracle plans no motion") == 1
    action = oracle._act_one(0, np.zeros(64))  # the observation is not even read
    assert action.tolist() == [0.0, 0.0, 0.0, 0.0, OPEN]


def test_eval_summary_counts_the_policy_notes():
    episodes = [{"outcome": "fail", "policy_note": "a: why"}] * 2 + [{"outcome": "success"}]
    assert EvalResult(episodes).summary()["policy_notes"] == {"a: why": 2}
    assert "policy_notes" not in EvalResult([{"outcome": "fail"}]).summary()
