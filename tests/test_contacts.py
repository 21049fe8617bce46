"""Scene facts, the hand's per-configuration roll and the contact-force strategy classifier."""

from __future__ import annotations

import numpy as np
import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.policies.heuristic_pull import HeuristicPull
from realikea.policies.rollout import final_info
from realikea.sim.ik import tcp_pitch
from realikea.tasks.contacts import SUMMARY_KEYS, ClassifierParams, ContactLog, strategy
from realikea.tasks.open_task import OpenTask

PARAMS = ClassifierParams(
    min_opening_rate=0.01,
    min_pull=0.2,
    min_samples=10,
    sample_substeps=5,
    friction_share=0.5,
    front_share=0.5,
)


def test_labels_follow_the_force_that_carries_the_pull():
    assert strategy(50, 0.9, 0.0, "two_point", PARAMS) == "pinch"
    assert strategy(50, 0.9, 0.0, "knob", PARAMS) == "pinch"
    assert strategy(50, 0.1, 0.0, "two_point", PARAMS) == "hook"
    assert strategy(50, 0.1, 0.0, "finger_pull", PARAMS) == "hook"
    assert strategy(50, 0.1, 0.0, "knob", PARAMS) == "lever"
    assert strategy(50, 0.1, 0.4, "knob", PARAMS) == "lever"  # the part still carries most
    assert strategy(50, 0.1, 0.8, "knob", PARAMS) == "front_hook"  # over the panel's edge
    assert strategy(50, 0.9, 0.8, "finger_pull", PARAMS) == "front_pinch"  # squeezing the panel
    assert strategy(9, 0.1, 0.0, "two_point", PARAMS) == "none"  # too short a pulling phase


def test_summary_shares_and_means():
    log = ContactLog(samples=20, normal=30.0, friction=90.0, grip=400.0)
    summary = log.summary("two_point", PARAMS, period=0.01)
    assert tuple(summary) == SUMMARY_KEYS  # the pool passes exactly these on
    assert summary["friction_share"] == pytest.approx(0.75)
    assert summary["pull_seconds"] == pytest.approx(0.2)
    assert summary["grip_force"] == pytest.approx(20.0)
    assert summary["strategy"] == "pinch"
    assert summary["front_share"] == 0.0
    panel = ContactLog(samples=20, normal=5.0, friction=5.0, front_normal=25.0, front_friction=5)
    assert panel.summary("finger_pull", PARAMS, 0.01)["front_share"] == pytest.approx(0.75)
    assert panel.summary("finger_pull", PARAMS, 0.01)["strategy"] == "front_hook"
    # a finger wedged between bar and panel presses the panel closed: that is no pull, and it
    # does not turn the hook's normal force into a friction-carried pull
    wedged = ContactLog(samples=20, normal=37.0, friction=10.0, front_normal=-31.0)
    summary = wedged.summary("two_point", PARAMS, 0.01)
    assert summary["friction_share"] == pytest.approx(10 / 47) and summary["front_share"] == 0.0
    assert summary["strategy"] == "hook"
    # friction pulling backwards does not make the normal forces' share larger than all
    assert ContactLog(samples=20, normal=30.0, friction=-5.0).summary("knob", PARAMS, 0.01)[
        "friction_share"
    ] == pytest.approx(0.0)


def _task(library, part: str, base: str, *extra: str) -> OpenTask:
    overrides = [f"asset.part={part}", f"asset.base={base}", "dr=randomized", "resistance=smooth"]
    cfg = load_config([*overrides, f"paths.library={library}", *extra], "eval")
    (mjcf,) = training_configurations(cfg, 1)
    return OpenTask(cfg, mjcf, seed=3)


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    return tmp_path_factory.mktemp("library")


def test_facts_place_the_part_frame_under_the_randomized_handle(library):
    task = _task(library, "tp_round_bar_128", "drawer_w60_h20")
    task.iteration = 10**6
    for _ in range(3):
        task.reset()
        facts = task.facts()
        local = facts.to_part(facts.handle_pos)
        assert local[:2] == pytest.approx([0.0, 0.0], abs=1e-9)  # the handle sits on the z axis
        assert local[2] > 0.0  # in front of the mount plane
        assert facts.to_world(local) == pytest.approx(facts.handle_pos)
        assert facts.pull_dir == pytest.approx(facts.part_rot[:, 2], abs=1e-9)  # out of the front
        assert facts.category == "two_point" and facts.joint_type == "slide"
        assert facts.hinge_axis is None


def test_door_hand_is_rolled_so_the_jaws_close_across_the_vertical_bar(library):
    task = _task(library, "tp_round_bar_128", "door_right_w60_h80")
    task.reset()
    facts = task.facts()
    rotation = task.data.site_xmat[task._tcp].reshape(3, 3)
    jaw_axis, bar_axis = rotation[:, 1], facts.part_rot[:, 0]
    assert abs(jaw_axis @ bar_axis) < 0.05  # jaws close across the bar
    assert abs(bar_axis[2]) > 0.99  # the bar is vertical on a door
    assert tcp_pitch(rotation, facts.tcp_nominal) == pytest.approx(0.0, abs=0.02)
    # opening direction: perpendicular to the hinge axis and to the lever arm
    arm = facts.handle_pos - facts.hinge_anchor
    assert abs(facts.pull_dir @ facts.hinge_axis) < 1e-9
    assert abs(facts.pull_dir @ arm) < 1e-9


def test_a_pinch_pull_is_classified_pinch(library):
    task = _task(library, "tp_round_bar_128", "drawer_w60_h20")
    info = final_info(task, HeuristicPull())
    assert info["outcome"] == "success"
    assert info["strategy"] == "pinch"
    assert info["friction_share"] > 0.9
    assert info["normal_angle_deg"] > 60  # jaw normals across the pull
    assert 0 < info["peak_slip_ratio"] < 1  # it held


def test_logging_contacts_does_not_change_the_physics(library):
    trajectories = []
    for log in ("true", "false"):
        task = _task(library, "tp_round_bar_128", "drawer_w60_h20", f"contacts.log={log}")
        rng = np.random.default_rng(0)
        task.reset()
        states = [task.step(rng.uniform(-1, 1, 5)).obs for _ in range(10)]
        trajectories.append(np.array(states))
    np.testing.assert_array_equal(trajectories[0], trajectories[1])


_PUSHER = """
<mujoco>
  <option timestep="0.002" gravity="0 0 0"/>
  <worldbody>
    <body name="front">
      <joint name="slide" type="slide" axis="1 0 0" damping="5"/>
      <geom name="panel" type="box" size="0.01 0.2 0.2" pos="0 0 0"/>
      <body name="part" pos="-0.03 0 0.1">
        <geom name="knob" type="sphere" size="0.015"/>
      </body>
    </body>
    <body name="hand" pos="-0.05 0 {z}">
      <joint name="push" type="slide" axis="1 0 0"/>
      <geom name="pad" type="box" size="0.02 0.02 0.02"/>
    </body>
  </worldbody>
  <actuator><motor joint="push" gear="20"/></actuator>
</mujoco>
"""


@pytest.mark.parametrize(
    ("z", "front_share", "label"), [(0.1, 0.0, "lever"), (-0.1, 1.0, "front_hook")]
)
def test_monitor_separates_forces_on_the_part_from_the_panel(z, front_share, label):
    """A pad pushes the front open along +x, level with the knob (a force on the part) or below
    it (on the panel): the pull is credited to where the pad touches."""
    import mujoco

    from realikea.sim.scene import subtree_geoms
    from realikea.tasks.contacts import ContactMonitor

    model = mujoco.MjModel.from_xml_string(_PUSHER.format(z=z))
    data = mujoco.MjData(model)
    panel, knob = model.geom("panel").id, model.geom("knob").id
    assert sorted(subtree_geoms(model, model.body("front").id)) == [panel, knob]
    monitor = ContactMonitor(model, [model.body("hand").id], [knob], [panel])
    log = ContactLog()
    data.ctrl[0] = 1.0
    u = np.array([1.0, 0.0, 0.0])
    for _ in range(300):
        mujoco.mj_step(model, data, nstep=5)
        monitor.record(log, monitor.forces(data), u, float(data.qvel[0]), PARAMS)
    summary = log.summary("knob", PARAMS, 0.01)
    assert log.samples > 100 and data.qpos[0] > 0.1  # pushed open
    assert summary["front_share"] == pytest.approx(front_share)
    assert summary["friction_share"] == pytest.approx(0.0, abs=0.01)  # a push: normal force
    assert summary["strategy"] == label


@pytest.mark.parametrize(("pad", "expected"), [(1.0, {0.6, 1.0}), (0.3, {0.3})])
def test_the_pads_friction_is_the_friction_of_their_contacts_with_the_front(library, pad, expected):
    """MuJoCo takes the larger coefficient of two geoms: the front's geoms are capped at the
    pads' (the presets' 1.0 leaves the part's 0.6 and the panel's 1.0 as built)."""
    from realikea.sim.scene import FRONT_BODY, subtree_geoms

    task = _task(library, "tp_round_bar_128", "drawer_w60_h20", f"gripper.pad_friction={pad}")
    model = task.model
    front = subtree_geoms(model, model.body(FRONT_BODY).id)
    assert set(np.round(model.geom_friction[front, 0], 3)) == expected
