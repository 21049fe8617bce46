"""The Franka finger near its tip, real vs simulated: thickness across the jaw gap and width,
slice by slice from the fingertip up, plus the pad's size and the tip's depth below the flange.

The real finger is Franka's CAD-derived visual mesh from franka_description, as shipped in
pybullet_data (`franka_panda/meshes/visual/finger.obj`, Apache-2.0, `franka_panda/LICENSE.txt`).
It has two parts: the white finger (material Part__Feature001_006, Kd 0.90) and the dark fingertip
pad (Part__Feature_007, Kd 0.25). Its frame is the URDF link `panda_leftfinger` (no visual offset),
mounted by `panda_finger_joint1` at 0.0584 m along the hand's approach axis and sliding along +y:
y points away from the other finger (the jaws meet at y = 0 when closed), z runs from the mount
towards the tip, x is the width. Our `left_finger` body uses the same frame (realikea/sim/robot.py),
so the mesh is read as is; the script checks this against the URDF and Franka's numbers (fingers
0.0584 m below the flange, TCP 0.1034 m at the pads' centre).

    python experiments/kitchen/fingertip_profile.py            # slices at 0 .. 30 mm
    python experiments/kitchen/fingertip_profile.py --d 0 1 2  # other distances (mm)

Prints the frame checks, the pads, a markdown table per slice (inner and outer face y, thickness,
width; real and ours) and the real tip's rounding and pad-face grooves.
"""

from __future__ import annotations

import argparse
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
import pybullet_data
import trimesh

from realikea.config import load_config
from realikea.sim.robot import FINGER_BODIES, GripperModel, robot_xml

FRANKA = Path(pybullet_data.getDataPath()) / "franka_panda"
MESH = FRANKA / "meshes" / "visual" / "finger.obj"
PAD_MATERIAL = "Part__Feature_007.001"  # the dark fingertip pad; the rest is the white finger
TIP_SLICE = 0.2e-3  # m: "d = 0" is sliced this far in (the end face is a plane of vertices)
DEFAULT_D = (0, 1, 2, 4, 6, 8, 10, 12, 15, 18, 21, 25, 30)


def load_finger(path: Path) -> tuple[trimesh.Trimesh, trimesh.Trimesh]:
    """The dark pad and the white finger, the OBJ's two parts (split by material)."""
    with warnings.catch_warnings():  # the OBJ's UV-less materials make trimesh warn about NaNs
        warnings.simplefilter("ignore", RuntimeWarning)
        parts = trimesh.load(path, force="scene", process=False, group_material=True).geometry
    pad = parts.pop(PAD_MATERIAL)
    (white,) = parts.values()
    return pad, white


def section(mesh: trimesh.Trimesh, z: float) -> np.ndarray:
    """Segments (m, 2, 3) where the mesh crosses the plane at height z."""
    return trimesh.intersections.mesh_plane(mesh, [0.0, 0.0, 1.0], [0.0, 0.0, z])


def face_y(segments: np.ndarray, x: float, y_below: float) -> float:
    """The smallest y at width x among segments crossing x with y < y_below (nan if none)."""
    best = np.nan
    for a, b in segments:
        if (a[0] - x) * (b[0] - x) <= 0 and a[0] != b[0]:
            y = a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0])
            if y < y_below and not y >= best:
                best = y
    return best


def urdf_checks() -> tuple[float, float]:
    """(finger mount, flange d) from panda.urdf, asserting the frame assumptions."""
    root = ET.parse(FRANKA / "panda.urdf").getroot()
    joints = {j.get("name"): j for j in root.iter("joint")}
    finger = joints["panda_finger_joint1"]
    mount = [float(v) for v in finger.find("origin").get("xyz").split()]
    assert mount[:2] == [0.0, 0.0] and finger.find("origin").get("rpy") == "0 0 0"
    assert finger.find("axis").get("xyz") == "0 1 0"
    assert finger.find("child").get("link") == "panda_leftfinger"
    hand = joints["panda_hand_joint"].find("origin").get("xyz")
    assert hand == "0 0 0", "the hand's origin is the flange"
    left = next(lk for lk in root.iter("link") if lk.get("name") == "panda_leftfinger")
    assert left.find("visual").find("origin") is None, "left finger mesh has no visual offset"
    flange = float(joints["panda_joint8"].find("origin").get("xyz").split()[2])
    return mount[2], flange


def sim_boxes() -> tuple[float, list[tuple[str, np.ndarray, np.ndarray]]]:
    """(mount below the flange, [(name, lo, hi)]) of our left finger's box geoms, finger frame."""
    gripper = GripperModel.from_config(load_config([]).gripper)
    model = mujoco.MjModel.from_xml_string(robot_xml(gripper, arm=False, visuals=False))
    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, FINGER_BODIES[0])
    assert np.allclose(model.body_quat[body], (1, 0, 0, 0))
    assert np.allclose(model.body_pos[body][:2], 0)
    boxes = []
    for g in np.flatnonzero(model.geom_bodyid == body):
        assert model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
        assert np.allclose(model.geom_quat[g], (1, 0, 0, 0))
        pos, half = model.geom_pos[g], model.geom_size[g]
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g)
        boxes.append((name, pos - half, pos + half))
    return float(model.body_pos[body][2]), boxes


def print_frames(mount, flange, vertices, pad_v, tip, sim_mount, boxes, sim_tip, sim_pad) -> None:
    """Where the real finger and ours sit below the flange, and the pads' sizes."""
    print(f"real finger: pybullet_data `{MESH.relative_to(FRANKA.parent)}` (franka_description's")
    licence = (FRANKA / "LICENSE.txt").relative_to(FRANKA.parent)
    print(f"  visual mesh; license `{licence}`, Apache-2.0)")
    print(f"  URDF: flange {flange} m after link7, hand at the flange, finger mount {mount} m")
    lo, hi = vertices.min(0) * 1e3, vertices.max(0) * 1e3
    print(
        f"  mesh bounds (mm): x {lo[0]:.1f}..{hi[0]:.1f} (width), y {lo[1]:.1f}..{hi[1]:.1f}",
        end="",
    )
    print(f" (from the jaw plane, outwards), z {lo[2]:.1f}..{hi[2]:.1f} (from the mount)")
    pad_c = (pad_v.min(0) + pad_v.max(0)) / 2
    print("frame checks (real | ours | Franka):")
    print(f"  tip below the flange (m): {mount + tip:.4f} | {sim_mount + sim_tip:.4f} | -")
    print(f"  pad centre below the flange (m): {mount + pad_c[2]:.4f} | ", end="")
    print(f"{sim_mount + (sim_pad[0][2] + sim_pad[1][2]) / 2:.4f} | 0.1034 (default TCP)")
    print(f"  finger mount below the flange (m): {mount} | {sim_mount:.4f} | 0.0584")
    print(
        f"  innermost y (mm, 0 = jaws touch when closed): {vertices[:, 1].min() * 1e3:.2f} | ",
        end="",
    )
    print(f"{min(lo[1] for _, lo, _ in boxes) * 1e3:.2f} | 0")
    size = (pad_v.max(0) - pad_v.min(0)) * 1e3
    print("pad (x width, y thickness, z length; mm):")
    print(f"  real, dark pad's bounding box: {size[0]:.1f} x {size[1]:.1f} x {size[2]:.1f}", end="")
    print(f", z {pad_v[:, 2].min() * 1e3:.1f}..{pad_v[:, 2].max() * 1e3:.1f} on the finger")
    ssize = (sim_pad[1] - sim_pad[0]) * 1e3
    print(f"  ours, box `{[n for n, *_ in boxes if n.endswith('pad')][0]}`: ", end="")
    print(f"{ssize[0]:.1f} x {ssize[1]:.1f} x {ssize[2]:.1f}", end="")
    print(f", z {sim_pad[0][2] * 1e3:.1f}..{sim_pad[1][2] * 1e3:.1f} on the finger")
    for name, lo, hi in boxes:
        print(f"  ours, box `{name}`: x {lo[0] * 1e3:.1f}..{hi[0] * 1e3:.1f}, ", end="")
        print(f"y {lo[1] * 1e3:.1f}..{hi[1] * 1e3:.1f}, z {lo[2] * 1e3:.1f}..{hi[2] * 1e3:.1f}")


def print_profile_table(ds, whole, pad_v, tip, boxes, sim_tip) -> None:
    """Thickness and width of both fingertips at each distance from the tip."""
    print()
    print(f"d: mm from the tip (d = 0 sliced {TIP_SLICE * 1e3:g} mm in); y from the jaw plane, mm;")
    print("thickness = outer - inner face (across the jaw gap); width along a grasped bar")
    print()
    print(
        "| d | real inner..outer y | real thick | real width | ours inner..outer y | ours thick",
        end="",
    )
    print(" | ours width | thick ours-real | width ours-real |")
    print("|---:|---|---:|---:|---|---:|---:|---:|---:|")
    for d in ds:
        dm = max(d * 1e-3, TIP_SLICE)
        seg = section(whole, tip - dm).reshape(-1, 3)
        r_in, r_out = seg[:, 1].min() * 1e3, seg[:, 1].max() * 1e3
        r_w = np.ptp(seg[:, 0]) * 1e3
        z = sim_tip - dm
        cut = [(lo, hi) for _, lo, hi in boxes if lo[2] <= z <= hi[2]]
        step = any(min(abs(z - lo[2]), abs(z - hi[2])) < 1e-6 for lo, hi in cut)
        s_in = min(lo[1] for lo, _ in cut) * 1e3
        s_out = max(hi[1] for _, hi in cut) * 1e3
        s_w = (max(hi[0] for _, hi in cut) - min(lo[0] for lo, _ in cut)) * 1e3
        groove = " g" if r_in > 0.5 and dm < np.ptp(pad_v[:, 2]) else ""
        row = f"| {d:g}{' s' if step else ''}{groove} | {r_in:.1f}..{r_out:.1f} "
        print(f"{row}| {r_out - r_in:.1f} | {r_w:.1f} ", end="")
        print(f"| {s_in:.1f}..{s_out:.1f} | {s_out - s_in:.1f} | {s_w:.1f} ", end="")
        print(f"| {s_out - s_in - (r_out - r_in):+.1f} | {s_w - r_w:+.1f} |")
    print()
    print("s: at our step from the pad to the finger body (both boxes' faces); g: the real pad's")
    print(
        "cross groove (its face recessed ~1.4 mm for d ~ 7.5-10.5 mm), real inner y is its bottom"
    )
    print()


def print_tip_profile(whole, pad, white, tip) -> None:
    """The real tip's profile: pad and finger thickness, width, the pad face and its groove."""
    print("real tip profile (mm from the tip: value)")
    for d in (0.5, 5, 15):
        p, w = (section(t, tip - d * 1e-3).reshape(-1, 3)[:, 1] * 1e3 for t in (pad, white))
        print(
            f"- d = {d:g}: dark pad y {p.min():.1f}..{p.max():.1f} ({np.ptp(p):.1f} thick), ",
            end="",
        )
        print(f"white finger behind it y {w.min():.1f}..{w.max():.1f} ({np.ptp(w):.1f} thick)")
    widths, outers, groove, flat = [], [], [], []
    for d in (0.05, 0.1, 0.2, 0.5, 1, 2, 3, 5, 8, 9, 12):
        seg = section(whole, tip - d * 1e-3)
        pts = seg.reshape(-1, 3)
        widths.append(f"{d:g}: {np.ptp(pts[:, 0]) * 1e3:.1f}")
        outers.append(f"{d:g}: {pts[:, 1].min() * 1e3:.1f}..{pts[:, 1].max() * 1e3:.1f}")
        groove.append(f"{d:g}: {face_y(seg, 0.0, 5e-3) * 1e3:.2f}")
        flat.append(f"{d:g}: {face_y(seg, 4e-3, 5e-3) * 1e3:.2f}")
    print(f"- width (x extent): {', '.join(widths)}")
    print(f"- inner..outer y: {', '.join(outers)}")
    print(f"- pad face y at x = 0 (centre line): {', '.join(groove)}")
    print(f"- pad face y at x = 4 mm: {', '.join(flat)}")
    seg = section(whole, tip - 5e-3)
    across = [f"{x:g}: {face_y(seg, x * 1e-3, 5e-3) * 1e3:.2f}" for x in np.arange(-3, 3.1, 0.5)]
    print(f"- pad face y across the centre line at d = 5 (x mm: y): {', '.join(across)}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--d", type=float, nargs="+", default=DEFAULT_D, help="mm from the tip")
    args = parser.parse_args()

    mount, flange = urdf_checks()
    pad, white = load_finger(MESH)
    whole = trimesh.util.concatenate([pad, white])
    vertices, pad_v = whole.vertices, pad.vertices
    tip = vertices[:, 2].max()
    sim_mount, boxes = sim_boxes()
    sim_tip = max(hi[2] for _, _, hi in boxes)
    sim_pad = next((lo, hi) for name, lo, hi in boxes if name.endswith("pad"))
    print_frames(mount, flange, vertices, pad_v, tip, sim_mount, boxes, sim_tip, sim_pad)
    print_profile_table(args.d, whole, pad_v, tip, boxes, sim_tip)
    print_tip_profile(whole, pad, white, tip)


if __name__ == "__main__":
    main()
