"""`realikea assets export`: URDF, USD and MJCF folders that reload in their own tools, with
metadata.json, written atomically and resumably, and refusing bad input before writing."""

from __future__ import annotations

import csv
import json
import math
import shutil

import mujoco
import numpy as np
import pybullet
import pytest
from conftest import EXPORT_SAMPLE
from pxr import Usd, UsdGeom, UsdPhysics

from realikea.cli import main
from realikea.errors import RealIkeaError
from realikea.export import driver
from realikea.export.driver import export_configurations, export_folder
from realikea.files import repo_path
from realikea.sim.resistance import handle_resistance, lever_arm, mode, nominal

REPORT_CSV = repo_path("experiments/fidelity/results/parts.csv")
HIGH = mode("high")  # what the fixture exports; the library is built at the nominal mode


def _configs(catalog, *names):
    return [
        next(catalog.configurations(part=EXPORT_SAMPLE[n][0], base=EXPORT_SAMPLE[n][1]))
        for n in names
    ]


@pytest.fixture(scope="module")
def exported(tmp_path_factory, export_library, catalog):
    """Every format of the three configurations with CoACD, and the drawer's hull URDF, in high."""
    out = tmp_path_factory.mktemp("export")
    configs = _configs(catalog, *EXPORT_SAMPLE)
    for fmt in driver.EXPORTERS:
        export_configurations(
            configs, fmt, "coacd", export_library, out, resistance=HIGH, progress=False
        )
    export_configurations(
        _configs(catalog, "drawer"), "urdf", "hull", export_library, out, resistance=HIGH,
        progress=False,
    )  # fmt: skip
    return out


def _id(name: str) -> str:
    return "__".join(EXPORT_SAMPLE[name])


def _built_model(export_library, name: str, source: str = "coacd") -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(export_library / _id(name) / f"model_{source}.xml"))


def _pieces(model: mujoco.MjModel) -> int:
    """Colliding geoms on the MJCF's part body."""
    part = model.body("part").id
    return sum(
        1 for g in range(model.ngeom) if model.geom_bodyid[g] == part and model.geom_contype[g]
    )


def _mujoco_pose(model: mujoco.MjModel, q: float, body: str) -> np.ndarray:
    """World position of a body with the front's joint at q."""
    data = mujoco.MjData(model)
    data.qpos[0] = q
    mujoco.mj_kinematics(model, data)
    return data.body(body).xpos.copy()


def _front_joint(model: mujoco.MjModel):
    joint = model.joint("front_joint")
    dof = joint.dofadr[0]
    return joint, model.dof_damping[dof], model.dof_frictionloss[dof]


def _at(model: mujoco.MjModel, resistance) -> tuple[float, float]:
    """(damping, frictionloss) of a built model's front joint in one mode, a hinge's scaled to
    its handle's lever arm."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    lever = lever_arm(data.xanchor[0], data.xaxis[0], data.site("handle").xpos)
    slide = model.jnt_type[0] == mujoco.mjtJoint.mjJNT_SLIDE
    return handle_resistance(
        "slide" if slide else "hinge", lever, resistance.damping, resistance.frictionloss
    )


# --------------------------------------------------------------------------------- URDF


@pytest.mark.parametrize(
    ("name", "source"), [(n, "coacd") for n in EXPORT_SAMPLE] + [("drawer", "hull")]
)
def test_urdf_loads_in_pybullet_with_the_mjcf_joint_and_one_shape_per_piece(
    exported, export_library, name, source
):
    model = _built_model(export_library, name, source)
    joint = _front_joint(model)[0]
    damping, frictionloss = _at(model, HIGH)
    urdf = export_folder(exported, "urdf", source, _id(name)) / f"model_{source}.urdf"
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(urdf), useFixedBase=True, physicsClientId=client)
        info = {
            pybullet.getJointInfo(body, i, physicsClientId=client)[1].decode(): i
            for i in range(pybullet.getNumJoints(body, physicsClientId=client))
        }
        front, part = info["front_joint"], info["part_weld"]
        _, _, kind, *_, jdamping, jfriction, lower, upper = pybullet.getJointInfo(
            body, front, physicsClientId=client
        )[:10]
        slide = model.jnt_type[joint.id] == mujoco.mjtJoint.mjJNT_SLIDE
        assert kind == (pybullet.JOINT_PRISMATIC if slide else pybullet.JOINT_REVOLUTE)
        assert (lower, upper) == pytest.approx(tuple(joint.range), abs=1e-9)
        assert jdamping == pytest.approx(damping, rel=1e-8)  # URDF: 9 digits
        assert jfriction == pytest.approx(frictionloss, rel=1e-8)

        def shapes(link):
            return len(pybullet.getCollisionShapeData(body, link, physicsClientId=client))

        assert shapes(-1) == 5  # the carcass's boxes
        assert shapes(front) == 1  # the front's inset collision box
        assert shapes(part) == _pieces(model)  # one per convex piece
        friction = pybullet.getDynamicsInfo(body, part, physicsClientId=client)[1]
        assert friction == pytest.approx(model.geom("part_collision_000").friction[0])
        for q in (0.0, joint.range[1] * 0.7):  # the part follows the joint as in MuJoCo
            pybullet.resetJointState(body, front, q, physicsClientId=client)
            state = pybullet.getLinkState(
                body, part, computeForwardKinematics=True, physicsClientId=client
            )
            assert state[4] == pytest.approx(_mujoco_pose(model, q, "part"), abs=1e-6)
    finally:
        pybullet.disconnect(client)


# --------------------------------------------------------------------------------- USD


def _physics(stage: Usd.Stage) -> dict:
    """UsdPhysics' own parse of the stage (what a simulator's importer reads), by object type."""
    parsed = UsdPhysics.UsdPhysicsLoadStageFromPrimRange(stage, ["/"])
    return {kind: list(zip(paths, descs, strict=True)) for kind, (paths, descs) in parsed.items()}


@pytest.mark.parametrize("name", list(EXPORT_SAMPLE))
def test_usd_reopens_as_an_articulation_with_convex_hull_pieces(exported, export_library, name):
    model = _built_model(export_library, name)
    joint = _front_joint(model)[0]
    damping, frictionloss = _at(model, HIGH)
    stage = Usd.Stage.Open(
        str(export_folder(exported, "usd", "coacd", _id(name)) / "model_coacd.usd")
    )
    root = stage.GetDefaultPrim()
    assert root.HasAPI(UsdPhysics.ArticulationRootAPI)
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    parsed = _physics(stage)
    T = UsdPhysics.ObjectType
    ((_, articulation),) = parsed[T.Articulation]
    slide = model.jnt_type[joint.id] == mujoco.mjtJoint.mjJNT_SLIDE
    ((path, desc),) = parsed[T.PrismaticJoint if slide else T.RevoluteJoint]
    assert path.name == "front_joint" and path in articulation.articulatedJoints
    assert desc.body0 == "" and desc.body1 == root.GetPath().AppendChild("front")  # fixed base
    to_unit = 1.0 if slide else 180 / math.pi  # revolute limits in degrees
    assert (desc.limit.lower, desc.limit.upper) == pytest.approx(
        tuple(joint.range * to_unit), rel=1e-6
    )
    per_unit = 1.0 if slide else math.pi / 180
    assert desc.drive.stiffness == 0 and desc.drive.damping == pytest.approx(damping * per_unit)
    prim = stage.GetPrimAtPath(path)
    instance = "linear" if slide else "angular"
    for effort in ("staticFrictionEffort", "dynamicFrictionEffort"):
        value = prim.GetAttribute(f"physxJointAxis:{instance}:{effort}").Get()
        assert value == pytest.approx(frictionloss, rel=1e-6)
    part = root.GetPath().AppendChild("part")
    pieces = [d for p, d in parsed[T.MeshShape] if p.GetParentPath() == part]
    assert len(pieces) == _pieces(model)
    assert all(d.approximation == UsdPhysics.Tokens.convexHull for d in pieces)
    visual = stage.GetPrimAtPath(part.AppendChild("part_visual"))
    assert visual.IsA(UsdGeom.Mesh) and not visual.HasAPI(UsdPhysics.CollisionAPI)
    world = UsdGeom.Xformable(stage.GetPrimAtPath(part)).ComputeLocalToWorldTransform(0)
    assert np.array(world.ExtractTranslation()) == pytest.approx(_mujoco_pose(model, 0, "part"))
    masses = {p.name: d for p, d in parsed[T.RigidBody]}
    assert set(masses) == {"front", "part"}
    mass = UsdPhysics.MassAPI(stage.GetPrimAtPath(part)).GetMassAttr().Get()
    assert mass == pytest.approx(model.body("part").mass[0], rel=1e-6)


# --------------------------------------------------------------------------------- MJCF


@pytest.mark.parametrize("name", list(EXPORT_SAMPLE))
def test_mjcf_is_the_built_model_at_the_exported_resistance(exported, export_library, name):
    built = _built_model(export_library, name)
    folder = export_folder(exported, "mjcf", "coacd", _id(name))
    copy = mujoco.MjModel.from_xml_path(str(folder / "model_coacd.xml"))
    assert (copy.nbody, copy.ngeom, copy.nmesh) == (built.nbody, built.ngeom, built.nmesh)
    assert _front_joint(built)[1:] == pytest.approx(_at(built, nominal()), rel=1e-5)
    assert _front_joint(copy)[1:] == pytest.approx(_at(built, HIGH), rel=1e-8)
    assert np.array_equal(copy.geom_size, built.geom_size)
    assert not any(p.name.startswith("hull") for p in (folder / "meshes").iterdir())


# --------------------------------------------------------------------------------- metadata


def _report_row(part_id: str) -> dict:
    with REPORT_CSV.open(newline="") as f:
        return next(r for r in csv.DictReader(f) if r["id"] == part_id)


def _metadata(out, fmt: str, source: str, name: str) -> dict:
    return json.loads((export_folder(out, fmt, source, _id(name)) / "metadata.json").read_text())


@pytest.mark.parametrize(("fmt", "source", "name"), [
    *(("usd", "coacd", n) for n in EXPORT_SAMPLE), ("urdf", "hull", "drawer"),
])  # fmt: skip
def test_metadata_describes_the_configuration(exported, export_library, catalog, fmt, source, name):
    meta = _metadata(exported, fmt, source, name)
    part, base = catalog.part(EXPORT_SAMPLE[name][0]), catalog.base(EXPORT_SAMPLE[name][1])
    assert (meta["config_id"], meta["part_id"], meta["base_id"]) == (_id(name), part.id, base.id)
    assert (meta["category"], meta["family"], meta["kind"]) == (
        part.category,
        part.family,
        base.kind,
    )
    assert meta["dimensions"]["part"] == part.dims
    assert meta["dimensions"]["base"]["width"] == base.width
    assert meta["joint"]["type"] == base.joint and meta["joint"]["range"] == [0.0, base.travel]
    # resistance: exported in high, every mode scaled to the handle as the scene scales it
    resistance = meta["resistance"]
    assert set(resistance["modes"]) == {"smooth", "normal", "high"}
    assert resistance["exported"]["mode"] == "high"
    damping, frictionloss = _at(_built_model(export_library, name, source), HIGH)
    assert resistance["exported"]["damping"] == pytest.approx(damping)
    assert resistance["modes"]["high"]["frictionloss"] == pytest.approx(frictionloss, rel=1e-5)
    if base.joint == "slide":
        assert resistance["lever_arm"] is None
        assert resistance["modes"] == resistance["at_handle"]
    else:
        r = resistance["lever_arm"]
        assert 0.05 < r < base.width + base.height
        assert resistance["modes"]["smooth"]["frictionloss"] == pytest.approx(5.0 * r)
        assert resistance["modes"]["smooth"]["damping"] == pytest.approx(2.0 * r**2)
    # bounds, masses
    size = meta["part_bounds"]["part_frame"]["size"]
    assert all(s > 0.005 for s in size)
    masses = meta["mass_model"]
    assert masses["links"]["part"]["mass"] > 0 and masses["links"]["carcass"]["mass"] == 0
    assert masses["moving_mass"] == pytest.approx(
        masses["links"]["front"]["mass"] + masses["links"]["part"]["mass"]
    )
    # the fidelity certificate is the report's row for this part and source
    certificate, row = meta["fidelity_certificate"], _report_row(part.id)
    assert certificate["source"] == source
    assert certificate["origin"] == "experiments/fidelity/results/parts.csv"
    for direction in ("q_to_p", "p_to_q"):
        for stat in ("mean", "median", "p90"):
            expected = float(row[f"{source}_{direction}_{stat}_m"])
            assert certificate[f"{direction}_m"][stat] == expected
    # what a 9 mm fingertip can use
    clearance = meta["fingertip_clearance"]
    assert clearance["fingertip"] == pytest.approx(0.009)
    if part.category == "knob":
        assert clearance["clearance"] is None and clearance["fits_fingertip"] is None
    else:
        assert 0.009 < clearance["clearance"] < 0.03 and clearance["fits_fingertip"]
    assert meta["export"]["format"] == fmt and meta["export"]["collision"] == source
    folder = export_folder(exported, fmt, source, _id(name))
    assert all((folder / f).is_file() for f in meta["export"]["files"])


def test_the_hull_certificate_swells_more_than_coacd(exported):
    coacd = _metadata(exported, "urdf", "coacd", "drawer")["fidelity_certificate"]
    hull = _metadata(exported, "urdf", "hull", "drawer")["fidelity_certificate"]
    assert hull["q_to_p_m"]["mean"] > 3 * coacd["q_to_p_m"]["mean"]


def test_a_part_missing_from_the_report_is_measured(export_library, catalog, tmp_path):
    (config,) = _configs(catalog, "flap")
    export_configurations(
        [config],
        "mjcf",
        "coacd",
        export_library,
        tmp_path,
        fidelity_csv=tmp_path / "no_report.csv",
        progress=False,
    )
    certificate = _metadata(tmp_path, "mjcf", "coacd", "flap")["fidelity_certificate"]
    assert certificate["origin"].startswith("measured at export")
    row = _report_row(config.part.id)  # the report's metric and defaults: the same numbers
    assert certificate["q_to_p_m"]["mean"] == pytest.approx(float(row["coacd_q_to_p_mean_m"]))


# --------------------------------------------------------------------------------- files


def test_a_relocated_folder_still_loads(export_library, catalog, tmp_path):
    """Exported from a copy of the export_library that is then deleted, and moved elsewhere."""
    (config,) = _configs(catalog, "door")
    copy = tmp_path / "export_library"
    shutil.copytree(export_library / config.id, copy / config.id)
    for fmt in driver.EXPORTERS:
        export_configurations([config], fmt, "coacd", copy, tmp_path / "out", progress=False)
    shutil.rmtree(copy)
    moved = tmp_path / "elsewhere"
    shutil.move(tmp_path / "out", moved)
    folder = {fmt: export_folder(moved, fmt, "coacd", config.id) for fmt in driver.EXPORTERS}
    assert mujoco.MjModel.from_xml_path(str(folder["mjcf"] / "model_coacd.xml")).nbody == 5
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(folder["urdf"] / "model_coacd.urdf"), physicsClientId=client)
        assert pybullet.getNumJoints(body, physicsClientId=client) == 2
        shapes = pybullet.getCollisionShapeData(body, 1, physicsClientId=client)
        assert all(s[4].decode().startswith(str(folder["urdf"])) for s in shapes)
    finally:
        pybullet.disconnect(client)
    stage = Usd.Stage.Open(str(folder["usd"] / "model_coacd.usd"))
    assert stage.GetDefaultPrim().HasAPI(UsdPhysics.ArticulationRootAPI)


def test_a_rerun_skips_complete_current_configurations(
    export_library, catalog, tmp_path, monkeypatch
):
    configs = _configs(catalog, "drawer", "door")
    first = export_configurations(
        configs, "urdf", "coacd", export_library, tmp_path, progress=False
    )
    assert (first.exported, first.current) == (2, 0)
    record = export_folder(tmp_path, "urdf", "coacd", configs[0].id) / "metadata.json"
    stamp = record.stat().st_mtime_ns
    again = export_configurations(
        configs, "urdf", "coacd", export_library, tmp_path, progress=False
    )
    assert (again.exported, again.current) == (0, 2) and record.stat().st_mtime_ns == stamp
    monkeypatch.setattr(driver, "EXPORT_VERSION", "changed")  # what it was made from changed
    redone = export_configurations(
        configs, "urdf", "coacd", export_library, tmp_path, progress=False
    )
    assert (redone.exported, redone.current) == (2, 0)


def test_an_interrupted_export_leaves_no_partial_folder(
    export_library, catalog, tmp_path, monkeypatch
):
    configs = _configs(catalog, "drawer", "flap", "door")
    written = driver.configuration_metadata
    calls = []

    def crash_on_the_second(*args):
        """Fails after the model and meshes of the second configuration are written."""
        calls.append(args[0].id)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return written(*args)

    monkeypatch.setattr(driver, "configuration_metadata", crash_on_the_second)
    with pytest.raises(KeyboardInterrupt):
        export_configurations(configs, "usd", "coacd", export_library, tmp_path, progress=False)
    parent = tmp_path / "usd_coacd"
    assert sorted(p.name for p in parent.iterdir()) == [configs[0].id]  # no staging left
    monkeypatch.setattr(driver, "configuration_metadata", written)
    report = export_configurations(
        configs, "usd", "coacd", export_library, tmp_path, progress=False
    )
    assert (report.exported, report.current) == (2, 1)
    assert sorted(p.name for p in parent.iterdir()) == sorted(c.id for c in configs)


# --------------------------------------------------------------------------------- bad input


def test_the_command_exports_one_configuration_at_the_mode_it_is_given(
    export_library, tmp_path, capsys
):
    part, base = EXPORT_SAMPLE["drawer"]
    args = ["--part", part, "--base", base, "--format", "mjcf", "--out", str(tmp_path)]
    library = f"paths.library={export_library}"
    assert main(["assets", "export", *args, "--resistance", "smooth", library]) == 0
    assert "exported 1, up to date 0" in capsys.readouterr().out
    folder = export_folder(tmp_path, "mjcf", "coacd", _id("drawer"))
    model = mujoco.MjModel.from_xml_path(str(folder / "model_coacd.xml"))
    assert _front_joint(model)[1:] == pytest.approx((2.0, 5.0))  # a drawer: the mode as given
    assert json.loads((folder / "metadata.json").read_text())["resistance"]["exported"] == {
        "mode": "smooth", "damping": 2.0, "frictionloss": 5.0
    }  # fmt: skip
    assert main(["assets", "export", *args, "--resistance", "high", library]) == 0
    assert "exported 1, up to date 0" in capsys.readouterr().out  # another mode: rewritten
    model = mujoco.MjModel.from_xml_path(str(folder / "model_coacd.xml"))
    assert _front_joint(model)[1:] == pytest.approx((10.0, 20.0))


@pytest.mark.parametrize("command", ["build", "export"])
def test_a_resistance_override_on_the_library_is_refused(export_library, tmp_path, capsys, command):
    """The library carries the nominal mode whatever the override says; saying so beats a
    silent no-op (an export 'at high' that is not)."""
    part, base = EXPORT_SAMPLE["drawer"]
    args = ["--part", part, "--base", base]
    if command == "export":
        args += ["--format", "mjcf", "--out", str(tmp_path / "out")]
    code = main(["assets", command, *args, "resistance=high", f"paths.library={export_library}"])
    assert code == 2
    err = capsys.readouterr().err
    assert "nominal resistance (normal)" in err
    assert ("--resistance" in err) and not (tmp_path / "out").exists()


def test_an_unknown_format_is_refused(export_library, catalog, tmp_path, capsys):
    out = tmp_path / "out"
    with pytest.raises(RealIkeaError, match="unknown export format 'obj'.*urdf, usd, mjcf"):
        export_configurations(_configs(catalog, "drawer"), "obj", "coacd", export_library, out)
    with pytest.raises(SystemExit):
        main(["assets", "export", "--all", "--format", "obj", "--out", str(out)])
    assert "invalid choice: 'obj'" in capsys.readouterr().err
    assert not out.exists()


def test_a_configuration_not_built_is_refused_with_how_to_build_it(
    export_library, tmp_path, capsys
):
    out = tmp_path / "out"
    args = ["--part", "knob_round_20", "--base", "flap_w60_h40", "--format", "urdf"]
    assert (
        main(["assets", "export", *args, "--out", str(out), f"paths.library={export_library}"]) == 2
    )
    err = capsys.readouterr().err
    assert "knob_round_20__flap_w60_h40" in err
    assert "realikea assets build --part knob_round_20 --base flap_w60_h40" in err
    assert not out.exists()


def test_an_out_that_is_a_file_is_refused(export_library, tmp_path, capsys):
    out = tmp_path / "taken.txt"
    out.write_text("mine")
    part, base = EXPORT_SAMPLE["drawer"]
    args = ["--part", part, "--base", base, "--format", "usd", "--out", str(out)]
    assert main(["assets", "export", *args, f"paths.library={export_library}"]) == 2
    assert f"--out {out} is an existing file" in capsys.readouterr().err
    assert out.read_text() == "mine" and sorted(tmp_path.iterdir()) == [out]


def test_the_cli_offers_exactly_the_formats_the_driver_exports():
    from realikea.export import FORMATS

    assert tuple(driver.EXPORTERS) == FORMATS
