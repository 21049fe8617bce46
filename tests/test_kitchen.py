"""The kitchen scene: fronts 3 mm from neighbours that never touch the opening front, the
robot placed by its lift, and scenes named by the config."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from omegaconf import OmegaConf

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.runs import run_scene
from realikea.policies.registry import make_policy
from realikea.policies.rollout import episode, final_info
from realikea.sim.scene import (
    FRONT_BODY,
    FRONT_JOINT,
    HANDLE_SITE,
    build_scene,
    placement,
    reset_home,
)
from realikea.tasks.open_task import OpenTask

OPENED = {"slide": 0.20, "hinge": 0.785}  # the success thresholds of realikea/conf/task/open.yaml


def _kitchen_geoms(model) -> list[int]:
    return [g for g in range(model.ngeom) if "kitchen_" in (model.geom(g).name or "")]


def _front_geoms(model) -> list[int]:
    """Every geom of the moving front and what is welded to it (the part)."""
    front = model.body(FRONT_BODY).id
    bodies = {b for b in range(model.nbody) if b == front or model.body_parentid[b] == front}
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] in bodies]


def _gap(model, data, geom_a: int, geoms: list[int]) -> float:
    """Smallest distance from one geom to any of the others (m), up to 5 cm."""
    fromto = np.zeros(6)
    return min(mujoco.mj_geomDistance(model, data, geom_a, g, 0.05, fromto) for g in geoms)


@pytest.fixture(scope="module")
def scenes(sample_library):
    """Default-config (kitchen) scenes of the sample's first part on every sample base."""
    out, _ = sample_library
    cfg = load_config(["resistance=high"])
    ids = sorted({p.parent.name for p in out.glob("*/model_coacd.xml")})
    part = ids[0].split("__")[0]
    return cfg, {
        i: build_scene(out / i / "model_coacd.xml", cfg) for i in ids if i.startswith(part)
    }


def test_neighbouring_fronts_stand_3_mm_from_the_front(scenes):
    cfg, models = scenes
    for config_id, model in models.items():
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        kitchen = _kitchen_geoms(model)
        assert kitchen, config_id
        fronts = [g for g in kitchen if "front" in model.geom(g).name]
        gap = _gap(model, data, model.geom("cabinet/front_visual").id, fronts)
        assert gap == pytest.approx(cfg.scene.front_gap, abs=2e-4), config_id


def test_the_front_opens_past_success_without_touching_the_kitchen(scenes):
    cfg, models = scenes
    for config_id, model in models.items():
        data = mujoco.MjData(model)
        reset_home(model, data, cfg)
        joint = model.joint(FRONT_JOINT)
        kind = "slide" if joint.type[0] == mujoco.mjtJoint.mjJNT_SLIDE else "hinge"
        kitchen, front = set(_kitchen_geoms(model)), set(_front_geoms(model))
        for q in np.linspace(0.0, 1.2 * OPENED[kind], 13):
            data.qpos[model.jnt_qposadr[joint.id]] = q
            mujoco.mj_forward(model, data)
            touching = [
                (model.geom(c.geom1).name, model.geom(c.geom2).name)
                for c in data.contact[: data.ncon]
                if {c.geom1, c.geom2} & front and {c.geom1, c.geom2} & kitchen
            ]
            assert not touching, (config_id, q, touching)


def test_the_lift_sets_the_robot_below_the_handle(scenes):
    cfg, models = scenes
    robot = cfg.scene.robot
    for config_id, model in models.items():
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        base, handle = data.body("link0").xpos, data.site(HANDLE_SITE).xpos
        lo, hi = robot.lift
        assert lo <= base[2] <= hi, config_id
        if lo < base[2] < hi:
            assert handle[2] - base[2] == pytest.approx(robot.handle_above_base), config_id
        assert base[0] - handle[0] == pytest.approx(robot.standoff), config_id
        assert base[1] == pytest.approx(handle[1]), config_id


def test_the_flap_hangs_in_a_wall_unit_and_drawers_stand_on_the_floor(scenes):
    cfg, models = scenes
    worktop = cfg.scene.plinth_height + cfg.scene.carcass_height + cfg.scene.worktop_thickness
    for config_id, model in models.items():
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        bottom = data.body("cabinet/unit").xpos[2]
        if "flap" in config_id:
            assert bottom == pytest.approx(worktop + cfg.scene.wall_unit_above_worktop)
        else:
            assert cfg.scene.plinth_height - 1e-9 <= bottom < worktop


def test_an_unknown_scene_lists_the_options():
    with pytest.raises(RealIkeaError, match="(?s)scene.*freestanding.*kitchen"):
        load_config(["scene=galley"])


def test_freestanding_keeps_the_old_layout(sample_library):
    out, _ = sample_library
    cfg = load_config(["scene=freestanding"])
    mjcf = next(out.glob("*__drawer_w60_h20/model_coacd.xml"))
    model = build_scene(mjcf, cfg)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    np.testing.assert_allclose(data.body("link0").xpos, cfg.sim.robot.base_pos)
    assert data.body("cabinet/unit").xpos[2] == pytest.approx(cfg.scene.plinth_height.drawer)
    assert not _kitchen_geoms(model)


ORACLE = ("policy=hook_oracle", "contacts.log=true")  # the oracle, its strategies labelled


def _task(tmp_path, part: str, base: str, *extra: str, seed: int = 0) -> OpenTask:
    """One configuration's task in high resistance, poses randomized (the draw `seed`)."""
    cfg = load_config(
        [f"asset.part={part}", f"asset.base={base}", "dr=randomized", "resistance=high",
         f"paths.library={tmp_path}", *extra],
        "eval",
    )  # fmt: skip
    return OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=seed)


def _episode(task: OpenTask) -> dict:
    """One episode of the task's configured scripted policy; the final step's info."""
    return final_info(task, make_policy(task.cfg))


@pytest.mark.parametrize("base", ["door_left_w60_h80", "door_right_w60_h80"])
def test_both_wide_doors_open_past_success_with_a_pinch(tmp_path, base):
    """The left-hinged door's arm starts from the mirror image of the home posture; from the
    right-hinged door's, the pull ran wrists 5 and 6 into their limits at about 0.7 rad."""
    cfg = load_config(
        ["asset.part=tp_round_bar_128", f"asset.base={base}", "dr=fixed",
         "policy=heuristic_pull", "resistance=smooth", f"paths.library={tmp_path}"],
        "eval",
    )  # fmt: skip
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    info = _episode(task)
    assert info["outcome"] == "success", (info["termination"], task.opening)


@pytest.mark.parametrize("base", ["door_left_w40_h80", "door_right_w40_h80"])
def test_hook_oracle_levers_a_door_knob_from_the_hinge_side(tmp_path, base):
    """On a door the knob's wedge comes from the hinge's side with the jaws straddling the head,
    and the wrist follows the door's whole turn: the door opens in high resistance by a lever.
    With the drawer's pitch both jaws pass the head on one side; with the wrist following 0.3
    of the turn the head turns off the pad."""
    for seed in (0, 1):
        task = _task(tmp_path, "knob_mushroom_38", base, *ORACLE, seed=seed)
        info = _episode(task)
        assert info["outcome"] == "success", (seed, info["termination"])
        assert info["strategy"] == "lever", (seed, info["strategy"])


def test_a_finger_pull_drawer_places_the_arm_below_its_handle_with_its_own_home(tmp_path):
    """A finger pull on a drawer is caught from below, the hand pitched up, which the arm's
    joint limits allow with the handle 0.15 m above its base (scene.robot.placements); a
    two-point drawer keeps the arm 0.80 m below the handle and sim.robot.home."""
    for part, above, placed in (("fp_cup_96", 0.15, True), ("tp_round_bar_128", 0.80, False)):
        task = _task(tmp_path, part, "drawer_w40_h20")
        task.reset()
        below = task.facts().handle_pos[2] - task.model.body("link0").pos[2]
        assert below == pytest.approx(above, abs=0.02), part  # the poses' jitter
        home = np.asarray(task.cfg.scene.robot.placements[0].home if placed else
                          task.cfg.sim.robot.home)  # fmt: skip
        np.testing.assert_allclose(task.home, home)


def test_a_placement_naming_no_category_is_refused(tmp_path):
    with pytest.raises(RealIkeaError, match=r"placements\[0\] names category 'finger'"):
        _task(tmp_path, "fp_cup_96", "drawer_w40_h20",
              "scene.robot.placements=[{category: finger, kind: drawer, handle_above_base: 0.2, "
              "home: [0, 0, 0, -1, 0, 1, 0]}]")  # fmt: skip


@pytest.mark.parametrize(
    "extra, match",
    [("hand_turnd: true", r"placements\[0\] has unknown keys hand_turnd"),
     ("hand_turned: 'no'", r"placements\[0\].hand_turned='no': true or false")],
)  # fmt: skip
def test_a_placement_with_a_bad_key_is_refused(tmp_path, extra, match):
    with pytest.raises(RealIkeaError, match=match):
        _task(tmp_path, "fp_cup_96", "door_left_w40_h80",
              "scene.robot.placements=[{category: finger_pull, kind: door, "
              f"handle_above_base: 0.8, home: [0, -1.5, 0, -2, 0, 1, 0], {extra}}}]")  # fmt: skip


def test_a_placement_home_outside_the_joint_limits_is_refused(tmp_path):
    with pytest.raises(RealIkeaError, match=r"placements\[0\].home"):
        _task(tmp_path, "fp_cup_96", "drawer_w40_h20",
              "scene.robot.placements=[{category: finger_pull, kind: drawer, "
              "handle_above_base: 0.2, home: [0, 0, 0, 0, 0, 1, 0]}]")  # fmt: skip


@pytest.mark.parametrize("part", ["fp_edge_64", "fp_lip_36", "fp_cup_96"])
def test_hook_oracle_hooks_a_finger_pull_drawer_from_below(tmp_path, part):
    """Placed with the handle 0.15 m above the arm's base, the hand pitches up 0.6 rad and the
    leading pad's tip goes up behind the lip: the drawer opens in high resistance by a hook
    (with the arm 0.80 m below the handle, none of the test finger pulls opened)."""
    task = _task(tmp_path, part, "drawer_w40_h20", *ORACLE)
    info = _episode(task)
    assert info["outcome"] == "success", (info["termination"], task.opening)
    assert info["strategy"] == "hook", info["strategy"]


def test_hook_oracle_hooks_the_finger_pull_flap_from_below_with_the_lift_raised(tmp_path):
    """The wall unit's flap is placed like a drawer's finger pull, its handle 0.15 m above the
    arm's base (the lift at 1.65 m): the lip's hook opens it past 45 deg in high resistance.
    On a 1.1 m lift the handle stays 0.70 m above the base, where the hand cannot pitch up
    behind the lip, and the flap stays shut (experiments/reach/README.md)."""
    task = _task(tmp_path, "fp_lip_36", "flap_w60_h40", *ORACLE)
    info = _episode(task)
    assert task.model.body("link0").pos[2] > 1.5
    assert info["outcome"] == "success" and info["strategy"] == "hook", (info, task.opening)
    low = _task(tmp_path, "fp_lip_36", "flap_w60_h40", *ORACLE, "scene.robot.lift=[0.0,1.1]")
    _episode(low)
    assert low.opening < OPENED["hinge"] / 2, low.opening


def test_a_knob_wedge_from_above_meets_the_worktop_and_from_below_it_levers(tmp_path, load_script):
    """With the arm 0.80 m below a drawer's knob (`placements=[]`) the wedge comes from above,
    and in draw 2 of this top drawer the hand's housing meets the worktop and the drawer stays
    shut (experiments/kitchen/hand_contacts.py names it); in draw 0 the wedge opens it touching
    nothing off the part. With the kitchen's placement (the handle 0.15 m above the base) the
    wedge comes from below and draw 2 opens by a lever."""
    module = load_script("experiments/kitchen/hand_contacts.py")
    high = ("scene.robot.placements=[]",)
    for extra, seed, expected in ((high, 2, "kitchen_worktop"), (high, 0, None), ((), 2, None)):
        cfg = _task(tmp_path, "knob_square_35", "drawer_w80_h20", *ORACLE, *extra).cfg
        task = module.HandContactTask(cfg, training_configurations(cfg, 1, 0)[0], seed=seed)
        info = _episode(task)
        first = info["first_off_part"]
        if expected is None:
            assert info["outcome"] == "success" and first is None, (extra, seed, first)
            assert info["strategy"] == "lever", (extra, seed, info["strategy"])
        else:
            assert info["outcome"] == "fail" and expected in first[0], (info["outcome"], first)


@pytest.mark.parametrize(
    "part, steps",
    [("fp_lip_36", ["start", "tip", "slide", "catch", "pull"]),
     ("tp_round_bar_128", ["start", "near", "catch", "close", "pull"])],
)  # fmt: skip
def test_hook_oracle_names_its_steps(tmp_path, part, steps):
    """Measurements read where an episode is in the oracle's plan by name
    (experiments/kitchen/wrist_load.py, loop_aperture.py): a lip's wedge, a bar's loop."""
    task = _task(tmp_path, part, "drawer_w40_h20", *ORACLE)
    policy = make_policy(task.cfg)
    seen = []
    for _ in episode(task, policy):
        name = policy.step(0)
        if not seen or seen[-1] != name:
            seen.append(name)
        if name == "pull":
            break
    assert seen == steps


def test_hook_oracle_hooks_a_finger_pull_door_with_the_hand_turned(tmp_path):
    """On a door the lip's wedge tips the rolled hand the way the wrist has 0.7 rad of range, and
    the pad comes off the lip as the pull starts: the door stays shut. With the hand turned half
    a turn (the kitchen's placement for finger-pull doors) the pad hooks the lip and the door
    turns (short of 45 deg in an episode: experiments/kitchen/README.md)."""
    turned = _task(tmp_path, "fp_lip_36", "door_left_w40_h80", *ORACLE)
    info = _episode(turned)
    assert info["strategy"] == "hook" and turned.opening > 0.2, (info["strategy"], turned.opening)
    plain = _task(tmp_path, "fp_lip_36", "door_left_w40_h80", *ORACLE, "scene.robot.placements=[]")
    _episode(plain)
    assert plain.opening < 0.05


def test_a_rerun_evaluates_a_run_in_the_scene_it_was_trained_in(tmp_path):
    """Before the kitchen: freestanding; a kitchen run from before the per-category placements:
    every arm 0.80 m below its handle; a later run: its own placements where today's default
    differs and its command line did not set them."""
    (tmp_path / "config.yaml").write_text("asset:\n  category: knob\n")
    assert run_scene(tmp_path) == ["scene=freestanding"]
    (tmp_path / "config.yaml").write_text("scene:\n  name: kitchen\n  robot:\n    standoff: 0.6\n")
    assert run_scene(tmp_path) == ["scene.robot.placements=[]"]
    (tmp_path / "config.yaml").write_text(
        "scene:\n  name: kitchen\n  robot:\n    placements:\n    - {category: finger_pull, "
        "kind: door, handle_above_base: 0.8, hand_turned: true, home: [0, -1.5, 0, -2, 0, 1, 0]}\n"
    )
    (override,) = run_scene(tmp_path)
    cfg = load_config(["scene=kitchen", override])
    (entry,) = cfg.scene.robot.placements
    assert entry.hand_turned is True and list(entry.home) == [0, -1.5, 0, -2, 0, 1, 0]
    assert placement(cfg, "finger_pull", "door").hand_turned
    (tmp_path / "overrides.yaml").write_text("- scene.robot.placements=[]\n")
    assert run_scene(tmp_path) == []  # its command line carries them
    (tmp_path / "overrides.yaml").unlink()
    today = load_config(["scene=kitchen"]).scene
    (tmp_path / "config.yaml").write_text(OmegaConf.to_yaml({"scene": today}))
    assert run_scene(tmp_path) == []  # today's default: nothing to pin
