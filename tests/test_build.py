"""The build: self-contained MJCF that compiles, no-op reruns, and exact cache invalidation."""

from __future__ import annotations

import csv
import dataclasses
import shutil

import mujoco
import pytest
from conftest import build_sample

from realikea.assets.build import INDEX_COLUMNS, build_library, part_key
from realikea.assets.library import load_model, read_index
from realikea.sim.resistance import handle_resistance, lever_arm, nominal
from realikea.sources import SOURCES


def test_every_sample_mjcf_compiles(sample_library, sample_configs):
    out, report = sample_library
    rows = read_index(out)
    assert len(rows) == len(sample_configs) == report.configs_built + report.configs_cached
    for row in rows:
        for source in SOURCES:
            model = mujoco.MjModel.from_xml_path(str(out / row[f"mjcf_{source}"]))
            assert model.njnt == 1 and model.nu == 0


def test_index_lists_config_part_base_category_joint(sample_library, sample_configs):
    out, _ = sample_library
    with (out / "index.csv").open() as f:
        reader = csv.DictReader(f)
        assert tuple(reader.fieldnames) == INDEX_COLUMNS
        rows = {r["config_id"]: r for r in reader}
    for config in sample_configs:
        row = rows[config.id]
        assert (row["part_id"], row["base_id"]) == (config.part.id, config.base.id)
        assert row["category"] == config.part.category
        assert row["joint_type"] == config.base.joint


def test_folder_is_self_contained(sample_library, tmp_path):
    out, _ = sample_library
    row = read_index(out)[0]
    moved = tmp_path / "elsewhere" / row["config_id"]
    shutil.copytree(out / row["config_id"], moved)
    for source in SOURCES:
        mujoco.MjModel.from_xml_path(str(moved / f"model_{source}.xml"))
    assert "/" not in (moved / "model_coacd.xml").read_text().split('file="')[1].split("meshes/")[0]


def test_coacd_has_many_pieces_and_hull_one(sample_library):
    out, _ = sample_library
    for row in read_index(out):
        coacd = mujoco.MjModel.from_xml_path(str(out / row["mjcf_coacd"]))
        hull = mujoco.MjModel.from_xml_path(str(out / row["mjcf_hull"]))
        assert coacd.nmesh - 1 >= 2, row["config_id"]
        assert hull.nmesh - 1 == 1


def test_joint_resistance_and_opening_direction(sample_library):
    out, _ = sample_library
    for row in read_index(out):
        model = load_model(out / row["mjcf_coacd"])
        data = mujoco.MjData(model)
        mujoco.mj_kinematics(model, data)
        lever = lever_arm(data.xanchor[0], data.xaxis[0], data.site("handle").xpos)
        mode = nominal()  # hinges: at the handle
        expected = handle_resistance(row["joint_type"], lever, mode.damping, mode.frictionloss)
        assert (model.dof_damping[0], model.dof_frictionloss[0]) == pytest.approx(
            expected, rel=1e-5
        )  # MJCF: 6 digits
        part = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "part_visual")
        mujoco.mj_forward(model, data)
        closed = data.geom_xpos[part].copy()
        data.qpos[0] = 0.5 * model.jnt_range[0, 1]
        mujoco.mj_forward(model, data)
        assert data.geom_xpos[part][0] > closed[0] + 0.05, "opening moves the handle outward"
        expected = "slide" if row["joint_type"] == "slide" else "hinge"
        assert mujoco.mjtJoint(model.jnt_type[0]).name.lower().endswith(expected)


def test_closed_front_does_not_touch_the_carcass(sample_library):
    """Step 3 keeps the tightly fitted front clear of its frame: no contact when closed."""
    out, _ = sample_library
    for row in read_index(out):
        model = load_model(out / row["mjcf_coacd"])
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        assert data.ncon == 0, row["config_id"]


def test_second_run_is_a_no_op(sample_library, sample_configs, settings, cache_root):
    out, _ = sample_library
    before = {p: p.stat().st_mtime_ns for p in out.glob("*/model_*.xml")}
    report = build_sample(sample_configs, settings, cache_root, out)
    assert (report.parts_built, report.configs_built) == (0, 0)
    assert report.configs_cached == len(sample_configs)
    assert before == {p: p.stat().st_mtime_ns for p in out.glob("*/model_*.xml")}


def test_changed_dimension_rebuilds_only_what_depends_on_it(catalog, settings, tmp_path):
    """One dimension changes: that part and its configurations rebuild, nothing else."""
    # cache logic, not CoACD quality: a concavity threshold this loose ends CoACD at its first
    # piece (about 0.5 s a knob in place of 15 s at 20 iterations of depth 2)
    quick = dataclasses.replace(settings.coacd, threshold=0.5, mcts_iterations=20, mcts_max_depth=2)
    settings = dataclasses.replace(settings, coacd=quick)
    changed, other = catalog.parts_in("knob")[:2]
    configs = [
        next(catalog.configurations(part=p.id, base="drawer_w60_h20")) for p in (changed, other)
    ]
    cache, out = tmp_path / "cache", tmp_path / "library"
    report = build_library(configs, settings, ("hull",), cache, out, progress=False)
    assert (report.parts_built, report.configs_built) == (2, 2)

    key = next(iter(changed.dims))
    edited = dataclasses.replace(changed, dims={**changed.dims, key: changed.dims[key] * 1.05})
    assert part_key(edited, settings) != part_key(changed, settings)
    configs[0] = dataclasses.replace(configs[0], part=edited)
    report = build_library(configs, settings, ("hull",), cache, out, progress=False)
    assert (report.parts_built, report.parts_cached) == (1, 1)
    assert (report.configs_built, report.configs_cached) == (1, 1)

    report = build_library(configs, settings, ("hull",), cache, out, progress=False)
    assert (report.parts_built, report.configs_built) == (0, 0)


def test_handle_site_sits_on_the_part(sample_library):
    """The `handle` site lies just inside the part's top surface, in front of the front."""
    out, _ = sample_library
    for row in read_index(out):
        model = load_model(out / row["mjcf_coacd"])
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        handle = data.site("handle").xpos
        front = data.geom("front_visual")
        outer_face = front.xpos[0] + model.geom("front_visual").size[0]
        assert outer_face < handle[0] < outer_face + 0.05, row["config_id"]


def test_the_index_skips_another_process_staging_folder(sample_library, tmp_path):
    """A configuration another process is still writing (its hidden staging folder) is not
    indexed: it may be renamed away between listing and reading."""
    from realikea.assets.build import write_index

    out, _ = sample_library
    library = tmp_path / "library"
    shutil.copytree(out, library)
    first = next(p for p in library.iterdir() if (p / "build.json").is_file())
    staging = library / f".{first.name}.abc123.tmp"
    shutil.copytree(first, staging)
    with (write_index(library)).open() as f:
        ids = [r["config_id"] for r in csv.DictReader(f)]
    assert len(ids) == len(set(ids)) == sum(1 for p in library.glob("[!.]*/build.json"))
