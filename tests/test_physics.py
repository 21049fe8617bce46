"""Physics of the library: resistance holds below its friction level; the hull seals handle gaps."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
import trimesh

from realikea.assets.build import build_parts
from realikea.assets.library import load_model, read_index
from realikea.interop.pull import pull_at_handle
from realikea.sim.resistance import nominal

# A Franka Hand fingertip: about 18 mm wide along the bar, 8 mm thick across the gap, 0.1 kg.
PROBE_HALF = (0.009, 0.008, 0.004)  # x (along bar), y (push direction), z (gap depth)
PROBE_FORCE = 5.0  # N pushing the probe down through the gap


def _at(model: mujoco.MjModel, damping: float, frictionloss: float) -> mujoco.MjModel:
    """The model with its (slide) front joint set to this damping and friction loss."""
    model.dof_damping[0], model.dof_frictionloss[0] = damping, frictionloss
    return model


def _pull_at_handle(model: mujoco.MjModel, force: float, seconds: float = 1.0) -> float:
    """Apply a constant outward pull at the handle and return the front joint's displacement."""
    data = mujoco.MjData(model)
    body = model.body("front").id
    handle = model.geom("part_visual").id
    for _ in range(int(seconds / model.opt.timestep)):
        data.qfrc_applied[:] = 0
        mujoco.mj_applyFT(
            model, data, np.array([force, 0, 0]), np.zeros(3), data.geom_xpos[handle], body,
            data.qfrc_applied,
        )  # fmt: skip
        mujoco.mj_step(model, data)
    return float(data.qpos[0])


def test_high_resistance_drawer_holds_below_friction_and_moves_above(sample_library):
    out, _ = sample_library
    row = next(r for r in read_index(out) if r["joint_type"] == "slide")
    model = _at(load_model(out / row["mjcf_coacd"]), 10.0, 20.0)
    assert abs(_pull_at_handle(model, 15.0)) < 1e-3  # 15 N < 20 N friction: stays shut
    assert _pull_at_handle(model, 30.0) > 0.1  # 30 N > 20 N: slides open


@pytest.mark.parametrize("mode", [(2.0, 5.0), (5.0, 10.0), (10.0, 20.0)])
def test_breakaway_force_tracks_the_friction_level(sample_library, mode):
    out, _ = sample_library
    row = next(r for r in read_index(out) if r["joint_type"] == "slide")
    damping, friction = mode
    model = _at(load_model(out / row["mjcf_coacd"]), damping, friction)
    assert abs(_pull_at_handle(model, 0.8 * friction, 0.5)) < 1e-3
    assert _pull_at_handle(model, 1.3 * friction, 0.5) > 0.01


def _gap_depth(visual: trimesh.Trimesh) -> float:
    """Clear depth from the mounting plane to the underside of the bar at the handle's centre."""
    hits, _, _ = visual.ray.intersects_location([[0.0, 0.0, 1e-4]], [[0.0, 0.0, 1.0]])
    assert len(hits), "a two-point handle has a bar above its centre"
    return float(hits[:, 2].min())


def _probe_model(pieces, gap: float, top: float) -> mujoco.MjModel:
    """Collision pieces fixed in the part frame and a finger-sized box sliding down (-y)."""
    meshes = "".join(f'<mesh name="m{i}" file="{p}"/>' for i, p in enumerate(pieces))
    geoms = "".join(f'<geom type="mesh" mesh="m{i}"/>' for i in range(len(pieces)))
    size = " ".join(map(str, PROBE_HALF))
    start = top + PROBE_HALF[1] + 0.002
    return mujoco.MjModel.from_xml_string(f"""
<mujoco>
  <option gravity="0 0 0" timestep="0.001"/>
  <default><geom solref="0.004 1"/></default>
  <asset>{meshes}</asset>
  <worldbody>
    {geoms}
    <body name="probe" pos="0 {start} {gap / 2}">
      <joint name="push" type="slide" axis="0 -1 0" damping="5"/>
      <geom type="box" size="{size}" mass="0.1"/>
    </body>
  </worldbody>
</mujoco>""")


def _push(model: mujoco.MjModel, seconds: float = 1.0) -> float:
    """Push the probe down with a constant force; return how far it travelled."""
    data = mujoco.MjData(model)
    for _ in range(int(seconds / model.opt.timestep)):
        data.qfrc_applied[0] = PROBE_FORCE
        mujoco.mj_step(model, data)
    return float(data.qpos[0])


def test_hull_seals_the_finger_gap_and_coacd_keeps_it_open(catalog, settings, cache_root):
    """For every two-point handle: a finger-sized probe passes behind the bar with CoACD only."""
    handles = catalog.parts_in("two_point")
    meshes, _ = build_parts(handles, settings, cache_root, progress=False)
    failures = []
    for part in handles:
        visual = trimesh.load_mesh(meshes[part.id].visual)
        gap = _gap_depth(visual)
        top, bottom = visual.bounds[1][1], visual.bounds[0][1]
        through = top - bottom + 2 * PROBE_HALF[1] + 0.004  # travel to clear the whole part
        coacd = _push(_probe_model(meshes[part.id].pieces["coacd"], gap, top))
        hull = _push(_probe_model(meshes[part.id].pieces["hull"], gap, top))
        if not (coacd > through and hull < 0.004):
            failures.append(
                f"{part.id}: gap {gap * 1e3:.1f} mm, coacd {coacd:.3f} m, hull {hull:.3f} m"
            )
    assert not failures, "\n".join(failures)


@pytest.mark.parametrize("kind", ["door", "flap"])
def test_hinged_fronts_break_away_at_the_handle_like_a_drawer(sample_library, kind):
    """The built MJCFs (the nominal mode: drawer friction 10 N) resist a pull at a door's or
    flap's handle with 10 N, not 10 N m: below it the front stays shut, above it it opens."""
    out, _ = sample_library
    rows = [r for r in read_index(out) if f"__{kind}_" in r["config_id"]]
    assert rows
    friction = nominal().frictionloss
    for row in rows:
        model = load_model(out / row["mjcf_coacd"])  # the resistance as built
        assert abs(pull_at_handle(model, 0.8 * friction, 0.5).q[-1]) < 2e-3, row["config_id"]
        assert pull_at_handle(model, 1.3 * friction, 0.5).q[-1] > 0.02, row["config_id"]
