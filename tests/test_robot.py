"""Robot, gripper, contact models, scene and IK: kinematics against the DH table, the hand's
grasp force and speed, the Coulomb pinch check, scene building and IK reach."""

from __future__ import annotations

import math

import mink
import mujoco
import numpy as np
import pytest

from realikea.assets.build import WorkflowSettings, build_library
from realikea.assets.catalog import Catalog
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.files import repo_path
from realikea.sim.ik import (
    VELOCITY_LIMIT,
    IKController,
    rolled_nominal,
    tcp_pitch,
    tcp_rotation,
)
from realikea.sim.resistance import handle_resistance
from realikea.sim.robot import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    DH_TABLE,
    FINGER_JOINTS,
    GRIPPER_ACTUATOR,
    HAND_BODY,
    HAND_YAW,
    TCP_Z,
    TORQUE_LIMIT,
    GripperModel,
    dh_flange_pose,
    gripper_ctrl,
    joint_limits,
    robot_xml,
)
from realikea.sim.scene import (
    FRONT_JOINT,
    HANDLE_SITE,
    TCP_SITE,
    build_scene,
    closed_front,
    reset_home,
)
from realikea.sources import SOURCES, built_model

PART = "tp_round_bar_128"
BASES = ("drawer_w60_h20", "door_right_w60_h80", "flap_w60_h40")
HAND_POS = (0.0, 0.0, 0.5)  # hand-only models: hand fixed here, approach pointing down


def gripper(name: str) -> GripperModel:
    return GripperModel.from_config(load_config([f"gripper={name}"]).gripper)


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """One two-point handle on a drawer, a door and the flap, both collision sources."""
    cfg = load_config()
    catalog = Catalog.load()
    configs = [c for b in BASES for c in catalog.configurations(part=PART, base=b)]
    out = tmp_path_factory.mktemp("sim_library")
    build_library(
        configs, WorkflowSettings.from_config(cfg),
        SOURCES, repo_path(cfg.paths.cache), out, workers=2, progress=False,
    )  # fmt: skip
    return out


# --- kinematics -------------------------------------------------------------------------------


def test_mjcf_forward_kinematics_matches_the_dh_table():
    model = mujoco.MjModel.from_xml_string(robot_xml(gripper("franka_hand")))
    data = mujoco.MjData(model)
    limits = joint_limits()
    rng = np.random.default_rng(0)
    c, s = math.cos(-HAND_YAW), math.sin(-HAND_YAW)
    unyaw = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])  # hand frame -> flange frame
    hand = model.body(HAND_BODY).id
    for _ in range(50):
        q = rng.uniform(limits[:, 0], limits[:, 1])
        data.qpos[:7] = q
        mujoco.mj_kinematics(model, data)
        flange = dh_flange_pose(q)
        np.testing.assert_allclose(data.xpos[hand], flange[:3, 3], atol=1e-6)
        np.testing.assert_allclose(data.xmat[hand].reshape(3, 3) @ unyaw, flange[:3, :3], atol=1e-6)
        tcp = data.site_xpos[model.site(TCP_SITE).id]
        np.testing.assert_allclose(tcp, flange[:3, 3] + TCP_Z * flange[:3, 2], atol=1e-6)


def test_joint_limits_actuators_and_mass():
    model = mujoco.MjModel.from_xml_string(robot_xml(gripper("franka_hand")))
    for name, act, (*_, lo, hi), tau in zip(
        ARM_JOINTS, ARM_ACTUATORS, DH_TABLE, TORQUE_LIMIT, strict=True
    ):
        joint = model.joint(name)
        assert joint.limited and tuple(joint.range) == pytest.approx((lo, hi))
        actuator = model.actuator(act)
        assert tuple(actuator.ctrlrange) == pytest.approx((lo, hi))
        assert tuple(actuator.forcerange) == pytest.approx((-tau, tau))
    for name in FINGER_JOINTS:
        assert tuple(model.joint(name).range) == pytest.approx((0.0, 0.04))
    assert model.nu == 8 and model.actuator(GRIPPER_ACTUATOR).trntype == mujoco.mjtTrn.mjTRN_TENDON
    assert 16.0 < model.body_subtreemass[model.body("link1").id] < 18.0  # moving arm + hand, kg


def test_gripper_command_maps_affinely():
    hand, servo = gripper("franka_hand"), gripper("menagerie_servo")
    assert gripper_ctrl(-1.0, hand) == pytest.approx(0.0)
    assert gripper_ctrl(1.0, hand) == pytest.approx(0.04)
    assert gripper_ctrl(0.0, servo) == pytest.approx(127.5)
    np.testing.assert_allclose(servo.ctrl(np.array([-1.0, 1.0, 3.0])), [0.0, 255.0, 255.0])
    assert servo.gain == pytest.approx(0.01568627451)  # Menagerie's gainprm
    assert (servo.kp, servo.kv, servo.force_limit) == (100.0, 10.0, 100.0)


def test_unknown_gripper_or_contact_is_a_clear_error():
    with pytest.raises(RealIkeaError, match="gripper"):
        load_config(["gripper=robotiq"])
    with pytest.raises(RealIkeaError, match="contact"):
        load_config(["contact=soft"])


# --- gripper physics (hand fixed in the world, a free object between the fingers) ------------


def hand_model(g: GripperModel, obj: str, half, cone="elliptic", impratio=10.0, gravity=False):
    """The hand with a free box or a horizontal bar (`obj` = box|bar) centred between the pads."""
    spec = mujoco.MjSpec.from_string(robot_xml(g, arm=False, hand_pos=HAND_POS))
    spec.option.cone = getattr(mujoco.mjtCone, f"mjCONE_{cone.upper()}")
    spec.option.impratio = impratio
    if not gravity:
        spec.option.gravity = [0, 0, 0]
    body = spec.worldbody.add_body(name="object", pos=[0, 0, HAND_POS[2] - TCP_Z])
    body.add_freejoint()
    geom = dict(name="object", mass=0.1, friction=[0.3, 0.005, 0.0001])
    if obj == "bar":  # a cylinder along x, the pads' width direction
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=half, quat=[1, 0, 1, 0], **geom)
    else:
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=half, **geom)
    return spec.compile()


def pad_normal_force(model, data, pad: str) -> float:
    """Total normal force between one pad and the object (N)."""
    pad_id, obj_id, force, total = model.geom(pad).id, model.geom("object").id, np.zeros(6), 0.0
    for i in range(data.ncon):
        contact = data.contact[i]
        if {contact.geom1, contact.geom2} == {pad_id, obj_id}:
            mujoco.mj_contactForce(model, data, i, force)
            total += force[0]
    return total


def close_on(model, g: GripperModel, width: float, seconds: float = 1.0) -> mujoco.MjData:
    data = mujoco.MjData(model)
    data.qpos[:2] = min(width / 2 + 0.004, g.stroke)
    data.ctrl[0] = g.ctrl(-1.0)
    for _ in range(int(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
    return data


@pytest.mark.parametrize("width", [0.012, 0.05])
def test_franka_hand_squeezes_with_70_n_whatever_the_width(width):
    g = gripper("franka_hand")
    model = hand_model(g, "box", (0.02, width / 2, 0.015))
    data = close_on(model, g, width)
    for pad in ("left_pad", "right_pad"):
        assert pad_normal_force(model, data, pad) == pytest.approx(70.0, rel=0.10)
    assert data.qpos[0] == pytest.approx(width / 2, abs=0.0015)  # pads press in < 1.5 mm


def test_franka_hand_closes_at_5_cm_per_second_per_finger():
    g = gripper("franka_hand")
    model = hand_model(g, "box", (0.02, 0.006, 0.015))
    data = mujoco.MjData(model)
    data.qpos[:2] = g.stroke
    data.qpos[4] = -5.0  # the object far away: free closing
    data.ctrl[0] = g.ctrl(-1.0)
    trace = []
    for _ in range(600):
        mujoco.mj_step(model, data)
        trace.append(data.qpos[0])
    trace = np.array(trace)
    t = np.arange(1, len(trace) + 1) * model.opt.timestep
    t_start, t_end = t[np.argmax(trace < 0.035)], t[np.argmax(trace < 0.010)]
    speed = 0.025 / (t_end - t_start)
    assert speed == pytest.approx(0.05, rel=0.30)


def test_menagerie_servo_grips_a_12_mm_bar_with_kp_times_half_width():
    g = gripper("menagerie_servo")
    model = hand_model(g, "bar", (0.006, 0.03))
    data = close_on(model, g, 0.012)
    expected = g.kp * 0.006  # N on the tendon; each jaw presses with half of it
    assert -data.actuator_force[0] == pytest.approx(expected, rel=0.30)
    for pad in ("left_pad", "right_pad"):
        assert pad_normal_force(model, data, pad) == pytest.approx(expected / 2, rel=0.30)


def slip_onset(cone: str, impratio: float, rate: float = 100.0) -> tuple[float, float]:
    """Ramp a pull on a pinched flat block along the pad plane; return (pull at slip, grip)."""
    g = gripper("franka_hand")
    model = hand_model(g, "box", (0.02, 0.015, 0.015), cone, impratio)
    data = close_on(model, g, 0.03, seconds=0.5)
    grip = pad_normal_force(model, data, "left_pad")
    body = model.body("object").id
    for k in range(int(4.0 * g.pad_friction * grip / rate / model.opt.timestep)):
        pull = rate * k * model.opt.timestep
        data.xfrc_applied[body, :3] = (0.0, 0.0, -pull)  # out of the jaws, along the pads
        mujoco.mj_step(model, data)
        if abs(data.qvel[2 + 2]) > 0.01:  # the block slides at more than 1 cm/s
            return pull, grip
    return math.inf, grip


def test_elliptic_pinch_slips_where_coulomb_says(record_property):
    g = gripper("franka_hand")
    pull, grip = slip_onset("elliptic", 10.0)
    coulomb = 2 * g.pad_friction * grip
    record_property("elliptic_slip_over_coulomb", pull / coulomb)
    print(f"elliptic: grip {grip:.1f} N, slip at {pull:.1f} N = {pull / coulomb:.2f} x 2 mu F")
    assert grip == pytest.approx(70.0, rel=0.10)
    assert pull == pytest.approx(coulomb, rel=0.20)


def test_pyramidal_pinch_creeps_below_coulomb(record_property):
    g = gripper("franka_hand")
    pull, grip = slip_onset("pyramidal", 1.0)
    coulomb = 2 * g.pad_friction * grip
    record_property("pyramidal_slip_over_coulomb", pull / coulomb)
    print(f"pyramidal: grip {grip:.1f} N, slip at {pull:.1f} N = {pull / coulomb:.2f} x 2 mu F")
    assert pull < 0.8 * coulomb  # the default cone lets the grasp go far below Coulomb's limit


# --- scene ---------------------------------------------------------------------------------


@pytest.mark.parametrize("source", ["coacd", "hull"])
@pytest.mark.parametrize("base", BASES)
def test_scene_builds_with_resistance_contact_and_layout(library, base, source):
    cfg = load_config(
        ["resistance=high", "contact=pyramidal", "gripper=menagerie_servo", "scene=freestanding"]
    )
    mjcf = built_model(library, f"{PART}__{base}", source)
    model = build_scene(mjcf, cfg)
    dof = model.jnt_dofadr[model.joint(FRONT_JOINT).id]
    front = closed_front(mjcf)  # hinges: the drawer's values scaled to the handle's lever arm
    expected = handle_resistance(front.joint_type, front.lever, 10.0, 20.0)
    assert (model.dof_damping[dof], model.dof_frictionloss[dof]) == pytest.approx(expected)
    assert model.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL and model.opt.impratio == 1.0
    assert model.opt.timestep == 0.002
    assert model.actuator(GRIPPER_ACTUATOR).ctrlrange[1] == 255.0
    data = mujoco.MjData(model)
    reset_home(model, data, cfg)
    np.testing.assert_allclose(data.xpos[model.body("link0").id], cfg.sim.robot.base_pos)
    handle = data.site(HANDLE_SITE).xpos
    base_z = cfg.sim.robot.base_pos[2]
    assert 0.5 < handle[2] - base_z < 0.9  # every handle in the arm's comfortable band
    assert data.ncon == 0  # nothing touches at home
    start = data.site(TCP_SITE).xpos.copy()
    for _ in range(250):
        mujoco.mj_step(model, data)
    assert np.linalg.norm(data.site(TCP_SITE).xpos - start) < 1e-3  # the arm holds its pose


def scripted_pinch_pull(mjcf, overrides, pull=0.3) -> tuple[float, float]:
    """Approach the handle level, pinch it, pull straight out at 10 cm/s through IK and the
    position actuators; return (front opening, slip of the TCP relative to the front), m."""
    cfg = load_config(overrides)
    model = build_scene(mjcf, cfg)
    data = mujoco.MjData(model)
    reset_home(model, data, cfg)
    base = model.body("link0").pos
    ik, grip = IKController.from_config(cfg, base_pos=base), GripperModel.from_config(cfg.gripper)
    arm = [model.jnt_qposadr[model.joint(j).id] for j in ARM_JOINTS]
    acts = [model.actuator(a).id for a in ARM_ACTUATORS]
    front = model.jnt_qposadr[model.joint(FRONT_JOINT).id]

    def control_step(target, command):
        data.ctrl[acts] = ik.solve(data.qpos[arm], target, 0.0).q
        data.ctrl[model.actuator(GRIPPER_ACTUATOR).id] = grip.ctrl(command)
        mujoco.mj_step(model, data, nstep=50)

    handle, start = data.site(HANDLE_SITE).xpos.copy(), data.site(TCP_SITE).xpos.copy()
    pre = handle + np.array([0.06, 0.0, 0.0])
    for k in range(1, 36):
        control_step(start + (pre - start) * min(k / 30, 1.0), 1.0)
    for k in range(1, 12):
        control_step(pre + (handle - pre) * min(k / 8, 1.0), 1.0)
    for _ in range(10):
        control_step(handle, -1.0)
    offset = data.site(TCP_SITE).xpos[0] - data.qpos[front]
    for k in range(1, round(pull / 0.01) + 1):
        control_step(handle + np.array([0.01 * k, 0.0, 0.0]), -1.0)
    return float(data.qpos[front]), float(data.site(TCP_SITE).xpos[0] - data.qpos[front] - offset)


def test_franka_hand_pinch_opens_a_stiff_drawer_where_the_menagerie_servo_slips(library):
    mjcf = built_model(library, f"{PART}__drawer_w60_h20", "coacd")
    opened, slip = scripted_pinch_pull(mjcf, ["resistance=high"])
    print(f"franka_hand/elliptic/high: opened {opened:.3f} m, slip {slip * 1000:.2f} mm")
    assert opened > 0.28 and abs(slip) < 0.002
    opened, slip = scripted_pinch_pull(mjcf, ["resistance=high", "gripper=menagerie_servo"])
    print(f"menagerie_servo/elliptic/high: opened {opened:.3f} m")
    assert opened < 0.01


def test_scene_rejects_a_missing_mjcf(tmp_path):
    with pytest.raises(RealIkeaError, match="not found"):
        build_scene(tmp_path / "missing.xml", load_config())
    with pytest.raises(RealIkeaError, match="build it first"):
        built_model(tmp_path, "nothing", "coacd")


# --- IK ------------------------------------------------------------------------------------


def test_pitch_round_trips():
    for pitch in (-0.6, 0.0, 0.3):
        assert tcp_pitch(tcp_rotation(pitch)) == pytest.approx(pitch)


@pytest.mark.parametrize("base", BASES)
def test_ik_reaches_a_target_near_each_handle(library, base):
    cfg = load_config()
    model = build_scene(built_model(library, f"{PART}__{base}", "coacd"), cfg)
    data = mujoco.MjData(model)
    reset_home(model, data, cfg)
    ik = IKController.from_config(cfg, base_pos=model.body("link0").pos)
    q = np.asarray(cfg.sim.robot.home, float)
    start, _ = ik.tcp_pose(q)
    target = data.site(HANDLE_SITE).xpos + np.array([0.03, 0.0, 0.0])  # just in front of it
    steps = int(np.ceil(np.linalg.norm(target - start) / 0.01))
    for k in range(1, steps + 10):  # 1 cm per call, as the policy moves, then hold
        result = ik.solve(q, start + (target - start) * min(k / steps, 1.0), 0.0)
        assert result.ok, (k, result)
        q = result.q
    assert result.position_error < 0.003 and result.rotation_error < 0.01
    limits = joint_limits()
    assert np.all(q >= limits[:, 0]) and np.all(q <= limits[:, 1])


def _mink_reference(ik: IKController, q, position, pitch: float):
    """IKController.solve written out plainly: mink.solve_ik on fresh tasks, then the checks."""
    lower, upper = joint_limits().T
    q = np.clip(np.asarray(q, float), lower, upper)
    configuration = mink.Configuration(ik.model)
    configuration.update(q)
    frame = mink.FrameTask(TCP_SITE, "site", position_cost=1.0, orientation_cost=1.0)
    rotation = mink.SO3.from_matrix(tcp_rotation(pitch, ik.nominal))
    frame.set_target(mink.SE3.from_rotation_and_translation(rotation, np.asarray(position, float)))
    posture = mink.PostureTask(ik.model, cost=float(ik.posture.cost[0]))
    posture.set_target(ik.home)
    limits = [
        mink.ConfigurationLimit(ik.model),
        mink.VelocityLimit(ik.model, dict(zip(ARM_JOINTS, VELOCITY_LIMIT, strict=True))),
    ]
    try:
        velocity = mink.solve_ik(
            configuration, [frame, posture], ik.dt, "daqp", damping=ik.damping, limits=limits
        )
    except mink.NoSolutionFound:
        return q, False, math.inf, math.inf
    q_new = configuration.integrate(velocity, ik.dt)
    inside = bool(np.all(q_new >= lower - 1e-6) and np.all(q_new <= upper + 1e-6))
    q_new = np.clip(q_new, lower, upper)
    configuration.update(q_new)
    reached = configuration.get_transform_frame_to_world(TCP_SITE, "site")
    position_error = float(np.linalg.norm(reached.translation() - position))
    rotation_error = float(np.linalg.norm((reached.rotation().inverse() @ rotation).log()))
    ok = (
        inside
        and position_error <= ik.position_tolerance
        and rotation_error <= ik.rotation_tolerance
    )
    return q_new, ok, position_error, rotation_error


@pytest.mark.parametrize("roll", [0.0, math.pi / 2])
def test_ik_step_equals_mink_solve_ik(roll):
    """The in-place QP gives mink.solve_ik's joint targets bit for bit, on random targets from
    random (partly out-of-range) configurations and along a tracked path that converges."""
    cfg = load_config()
    ik = IKController.from_config(cfg, nominal=rolled_nominal(roll))
    home = np.asarray(cfg.sim.robot.home, float)
    start, _ = ik.tcp_pose(home)
    rng = np.random.default_rng(7)
    cases = [
        (home + rng.normal(0, 0.3, 7), start + rng.uniform(-0.3, 0.3, 3), rng.uniform(-0.6, 0.6))
        for _ in range(200)
    ]
    q, path = home, []
    for k in range(60):  # small steps, then holding still: residuals shrink towards zero
        target = start + np.array([0.1, 0.05, -0.05]) * min(k / 30, 1.0)
        path.append((q, target, 0.2 * min(k / 30, 1.0)))
        q = ik.solve(q, target, path[-1][2]).q
    oks = []
    for q, target, pitch in cases + path:
        result = ik.solve(q, target, pitch)
        q_ref, ok_ref, position_ref, rotation_ref = _mink_reference(ik, q, target, pitch)
        assert np.array_equal(result.q, q_ref)
        assert result.ok == ok_ref
        assert result.position_error == pytest.approx(position_ref, rel=1e-12, abs=1e-15)
        # the arccos of the trace resolves angles near zero only to ~1e-8 rad
        assert result.rotation_error == pytest.approx(rotation_ref, abs=3e-8)
        oks.append(result.ok)
    assert 0 < sum(oks) < len(oks)  # both outcomes covered
    assert path and result.ok and result.rotation_error < 1e-3


def test_ik_flags_an_unreachable_target():
    cfg = load_config()
    ik = IKController.from_config(cfg)
    q = np.asarray(cfg.sim.robot.home, float)
    pos, _ = ik.tcp_pose(q)
    far = pos + np.array([-2.0, 0.0, 0.0])
    for _ in range(20):
        result = ik.solve(q, far, 0.0)
        assert not result.ok
        limits = joint_limits()
        assert np.all(result.q >= limits[:, 0]) and np.all(result.q <= limits[:, 1])
        q = result.q
