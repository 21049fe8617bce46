"""The Panda's meshes (realikea/sim/panda_visuals.py) are looks only: with and without them the
robot has the same collision geoms, masses and inertias, and a task's state is bit-identical
over 200 control steps of the same actions. The checks themselves catch a visual geom that
collides or weighs something."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

import realikea.tasks.open_task as open_task
from realikea.assets.build import WorkflowSettings, build_library
from realikea.assets.catalog import Catalog
from realikea.config import load_config
from realikea.files import repo_path
from realikea.sim.panda_visuals import SOURCES, panda_dir, panda_pieces
from realikea.sim.robot import (
    ARM_ACTUATORS,
    COLLISION_GROUP,
    FINGER_BODIES,
    GRIPPER_ACTUATOR,
    HAND_BODY,
    VISUAL_GROUP,
    GripperModel,
    robot_xml,
)
from realikea.sim.scene import build_scene, subtree_geoms
from realikea.sources import built_model

CONFIG = ("knob_round_30", "drawer_w60_h20")  # a knob on a drawer: the hand reaches and pulls
ROBOT_BODIES = (*(f"link{i}" for i in range(8)), HAND_BODY, *FINGER_BODIES)
HOME = np.array([-0.34, -0.52, 0.08, -2.06, 1.51, 2.87, 0.89])
BOX_HALF = 0.015  # m, half the held box's width between the pads


def gripper() -> GripperModel:
    return GripperModel.from_config(load_config([]).gripper)


def robot_spec(visuals: bool) -> mujoco.MjSpec:
    """The robot on a floor with a free box between its fingers (contacts on both pads)."""
    spec = mujoco.MjSpec.from_string(robot_xml(gripper(), visuals=visuals))
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_PLANE, size=[2, 2, 0.1])
    model = mujoco.MjModel.from_xml_string(robot_xml(gripper(), visuals=False))
    data = mujoco.MjData(model)
    data.qpos[:7] = HOME
    mujoco.mj_kinematics(model, data)
    body = spec.worldbody.add_body(
        name="held", pos=data.site("tcp").xpos, quat=data.body(HAND_BODY).xquat
    )
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.01, BOX_HALF, 0.01], mass=0.2)
    return spec


def collision_geoms(model: mujoco.MjModel) -> list[tuple]:
    """Every geom that can collide, as everything the contacts read of it."""
    rows = []
    for g in range(model.ngeom):
        if not (model.geom_contype[g] or model.geom_conaffinity[g]):
            continue
        rows.append((
            model.geom(g).name, model.body(model.geom_bodyid[g]).name, int(model.geom_type[g]),
            *model.geom_size[g], *model.geom_pos[g], *model.geom_quat[g],
            int(model.geom_contype[g]), int(model.geom_conaffinity[g]), int(model.geom_condim[g]),
            int(model.geom_priority[g]), *model.geom_friction[g], *model.geom_solref[g],
            *model.geom_solimp[g], model.geom_margin[g], model.geom_gap[g],
            model.geom_rbound[g], *model.geom_aabb[g],
        ))  # fmt: skip
    return rows


def inertias(model: mujoco.MjModel) -> list[tuple]:
    """Every body's name, mass, inertia and the frames they are given in."""
    return [
        (model.body(b).name, model.body_mass[b], *model.body_inertia[b], *model.body_ipos[b],
         *model.body_iquat[b], model.body_subtreemass[b])
        for b in range(model.nbody)
    ]  # fmt: skip


def assert_same_dynamics_model(with_meshes: mujoco.MjModel, without: mujoco.MjModel) -> None:
    assert collision_geoms(with_meshes) == collision_geoms(without)
    assert inertias(with_meshes) == inertias(without)
    sizes = ("nq", "nv", "nu", "na", "nbody", "njnt", "neq", "ntendon")
    assert [getattr(with_meshes, k) for k in sizes] == [getattr(without, k) for k in sizes]


def rollout(model: mujoco.MjModel, steps: int = 200) -> tuple[np.ndarray, np.ndarray, int]:
    """qpos and qvel after each of `steps` control periods (25 physics steps) of fixed commands:
    the fingers squeeze the box while the arm swings it; and the most robot contacts at once."""
    data = mujoco.MjData(model)
    data.qpos[:7], data.qpos[7:9] = HOME, BOX_HALF  # the pads just touch the box
    arm = [model.actuator(a).id for a in ARM_ACTUATORS]
    data.act[:] = HOME
    grip = model.actuator(GRIPPER_ACTUATOR).id
    robot = {model.body(b).id for b in ROBOT_BODIES}
    qpos, qvel, most = [], [], 0
    for k in range(steps):
        bend = 0.25 * np.sin(np.pi * k / 50)
        data.ctrl[arm] = HOME + bend * np.array([0.3, 1.0, 0.0, -0.5, 0.0, 0.5, 0.2])
        data.ctrl[grip] = 0.0
        mujoco.mj_step(model, data, nstep=25)
        qpos.append(data.qpos.copy())
        qvel.append(data.qvel.copy())
        bodies = model.geom_bodyid[data.contact.geom[: data.ncon]]
        most = max(most, int(np.isin(bodies, list(robot)).any(axis=1).sum()))
    return np.array(qpos), np.array(qvel), most


def test_meshes_come_from_pybullet_data_with_its_licence():
    folder = panda_dir()
    assert "Apache License" in (folder / "LICENSE.txt").read_text()
    pieces = panda_pieces()
    assert set(pieces) == set(SOURCES)
    for body, parts in pieces.items():
        assert parts and all(p.file.is_file() and p.file.is_absolute() for p in parts), body


def test_meshes_are_drawn_and_never_collide_or_weigh():
    spec = mujoco.MjSpec.from_string(robot_xml(gripper()))
    assert spec.compiler.inertiafromgeom != mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    for name in ROBOT_BODIES:  # explicit inertials: MuJoCo infers nothing from the geoms
        assert spec.body(name).explicitinertial, name
    for geom in spec.geoms:  # no mass, even were the inertia ever inferred from the geoms
        assert geom.type != mujoco.mjtGeom.mjGEOM_MESH or geom.mass == 0, geom.name
    model = spec.compile()
    meshes = np.flatnonzero(model.geom_type == mujoco.mjtGeom.mjGEOM_MESH)
    pieces = panda_pieces()
    assert len(meshes) == sum(len(p) for p in pieces.values()) + len(pieces["finger"])  # 2 fingers
    assert {model.body(model.geom_bodyid[g]).name for g in meshes} == set(ROBOT_BODIES)
    for g in meshes:
        assert (model.geom_contype[g], model.geom_conaffinity[g]) == (0, 0)
        assert model.geom_group[g] == VISUAL_GROUP
    drawn = mujoco.MjvOption().geomgroup  # what a renderer shows by default
    colliding = [
        g for g in range(model.ngeom) if model.geom_contype[g] or model.geom_conaffinity[g]
    ]
    assert drawn[VISUAL_GROUP] and not drawn[COLLISION_GROUP]
    assert colliding and all(model.geom_group[g] == COLLISION_GROUP for g in colliding)


def test_robot_dynamics_are_bit_identical_without_meshes():
    with_meshes, without = robot_spec(True).compile(), robot_spec(False).compile()
    assert_same_dynamics_model(with_meshes, without)
    qpos, qvel, contacts = rollout(with_meshes)
    qpos0, qvel0, _ = rollout(without)
    assert contacts >= 2  # both pads on the box
    assert np.array_equal(qpos, qpos0) and np.array_equal(qvel, qvel0)


@pytest.mark.parametrize("flaw", ["mass", "contact"])
def test_the_checks_catch_a_visual_geom_that_weighs_or_collides(flaw):
    spec, plain = robot_spec(True), robot_spec(False)
    geom = spec.geom("hand_visual0")
    if flaw == "mass":  # weighed once MuJoCo infers the bodies' inertia from their geoms
        for s in (spec, plain):
            s.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
        geom.mass = 0.3
    else:
        geom.contype, geom.conaffinity = 2, 1
    with_flaw, without = spec.compile(), plain.compile()
    with pytest.raises(AssertionError):
        assert_same_dynamics_model(with_flaw, without)
    if flaw == "mass":
        qpos, _, _ = rollout(with_flaw, 50)
        assert not np.array_equal(qpos, rollout(without, 50)[0])


@pytest.fixture(scope="module")
def library(tmp_path_factory) -> Path:
    cfg = load_config()
    part, base = CONFIG
    out = tmp_path_factory.mktemp("visuals_library")
    build_library(
        list(Catalog.load().configurations(part=part, base=base)),
        WorkflowSettings.from_config(cfg), ("coacd",), repo_path(cfg.paths.cache), out,
        workers=1, progress=False,
    )  # fmt: skip
    return out


def test_task_state_is_bit_identical_without_meshes(library, monkeypatch):
    """200 control steps of the same actions (reach the knob, close, pull) in the kitchen."""
    mjcf = built_model(library, "__".join(CONFIG), "coacd")
    cfg = load_config(["resistance=high", "dr=randomized"])
    assert_same_dynamics_model(build_scene(mjcf, cfg), build_scene(mjcf, cfg, visuals=False))
    states = {}
    for visuals in (True, False):
        monkeypatch.setattr(
            open_task, "build_scene", lambda *a, v=visuals: build_scene(*a, visuals=v)
        )
        task = open_task.OpenTask(cfg, mjcf, seed=3)
        n_mesh = int(np.sum(task.model.geom_type == mujoco.mjtGeom.mjGEOM_MESH))
        robot = subtree_geoms(task.model, task.model.body("link0").id)
        obs, rows, touched = [task.reset()], [], 0
        for k in range(200):
            action = [0.0, -0.6, 0.0, 0.0, 1.0] if k < 100 else [0.0, 1.0, 0.0, 0.0, -1.0]
            result = task.step(np.array(action))
            obs.append(result.obs)
            rows.append((task.data.qpos.copy(), task.data.qvel.copy(), result.reward))
            geoms = task.data.contact.geom[: task.data.ncon]
            touched = max(touched, int(np.isin(geoms, robot).any(axis=1).sum()))
            if result.terminated or result.truncated:
                obs.append(task.reset())
        states[visuals] = (n_mesh, np.array(obs), rows, touched)
    (meshes, obs, rows, touched), (none, obs0, rows0, _) = states[True], states[False]
    assert meshes > none and touched > 0  # the hand pressed on the front
    assert np.array_equal(obs, obs0)
    for (qpos, qvel, reward), (qpos0, qvel0, reward0) in zip(rows, rows0, strict=True):
        assert np.array_equal(qpos, qpos0) and np.array_equal(qvel, qvel0)
        assert reward == reward0
