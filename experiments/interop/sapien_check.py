"""The exported URDFs in SAPIEN against the exported MJCFs in MuJoCo; writes results/sapien.md.

    pip install -e '.[interop]'   # SAPIEN 3.0.3, an extra: not needed by the rest of the project
    nice -n 10 python experiments/interop/sapien_check.py [--work DIR] [--out FILE]

The six configurations of pybullet_parity.py (two per kind, every category twice), exported to
URDF and MJCF (CoACD) at high and smooth resistance as pybullet_parity.py does, are loaded with
SAPIEN's URDF loader into a CPU PhysX scene (no renderer: the URDF's <visual> elements are
dropped before loading, since SAPIEN builds render materials for them and this machine has no
Vulkan device) and pulled at the handle with 0.5x, 1.2x and 2x their breakaway force for 1 s,
as pybullet_parity.py does in PyBullet, twice: as loaded, and with the joint friction emulated.

As loaded, SAPIEN 3.0.3 makes the URDF's <dynamics damping> a joint drive (stiffness 0,
damping c) and stores <dynamics friction> without applying it (PhysX's own joint friction
coefficient stays at its default, 0.05, a unitless coefficient, not a force). Emulation: the
drive becomes a velocity drive of target 0 with a large damping (BIG) capped at the friction
(Coulomb friction, as pybullet_parity.py's capped PyBullet motor), the damping is applied by
hand as a joint force -c v, PhysX's joint friction coefficient is set to 0, and the links'
default linear and angular damping (PhysX's 0.05) to 0, since the MJCF has none.
"""

from __future__ import annotations

import re
import sys
import tempfile
import time
import warnings
from importlib.metadata import version
from pathlib import Path

import numpy as np

from realikea.export.metadata import PART_LINK
from realikea.export.model import read_articulation
from realikea.files import repo_path
from realikea.interop.parity import SECONDS, compare_pull
from realikea.interop.pull import Trajectory, mujoco_pull, opening_direction
from realikea.interop.sample import (
    MULTIPLES,
    SAMPLE_MODES,
    UNIT,
    Prepared,
    prepare,
    sample_arguments,
    sample_context,
)

DEFAULT_OUT = repo_path("experiments/interop/results/sapien.md")
BIG = 1e5  # drive damping of the emulated friction (N s/m, N m s/rad): a stiff velocity hold
MODELS = ("emulated", "as loaded")


def sapien_pull(item: Prepared, force: float, model: str, timestep: float) -> Trajectory:
    """Pull an exported URDF in SAPIEN (CPU PhysX) at the handle with `force` newtons along its
    direction of opening, the joint's friction `model` being emulated or as loaded."""
    import sapien
    from sapien import physx

    scene = sapien.Scene([physx.PhysxCpuSystem()])
    scene.set_timestep(timestep)
    loader = scene.create_urdf_loader()
    loader.fix_root_link = True
    text = re.sub(r"<visual.*?</visual>", "", item.urdf.read_text(), flags=re.S)
    physics_only = item.urdf.with_name(".physics_only.urdf")
    physics_only.write_text(text)
    try:
        articulation = loader.load(str(physics_only))
    finally:
        physics_only.unlink()
    (joint,) = articulation.get_active_joints()
    part = articulation.find_link_by_name("part")
    resistance = item.metadata["resistance"]["exported"]
    damping, friction = resistance["damping"], resistance["frictionloss"]
    if model == "emulated":
        for link in articulation.get_links():
            link.set_linear_damping(0.0)
            link.set_angular_damping(0.0)
        joint.friction = 0.0
        joint.set_drive_property(0.0, BIG, friction)
        joint.set_drive_velocity_target(0.0)
    # the part link's frame is the MJCF part body's (urdf.py); SAPIEN's link poses are set only
    # by the first step, so the handle is carried into it from the MJCF, front closed
    to_part = np.linalg.inv(read_articulation(item.mjcf).link(PART_LINK).pose)
    on_part = (to_part @ np.r_[item.handle, 1.0])[:3]
    anchor, axis = item.joint["anchor"], item.joint["axis"]
    q = np.empty(int(round(SECONDS / timestep)))
    for step in range(len(q)):
        point = (part.get_entity_pose().to_transformation_matrix() @ np.r_[on_part, 1.0])[:3]
        direction = opening_direction(item.joint["type"], anchor, axis, point)
        part.add_force_at_point((force * direction).astype(np.float32), point.astype(np.float32))
        if model == "emulated":
            articulation.set_qf(np.array([-damping * articulation.get_qvel()[0]], np.float32))
        scene.step()
        q[step] = articulation.get_qpos()[0]
    return Trajectory(timestep, q)


def _q(value: float, joint_type: str) -> str:
    """An opening with its unit."""
    return f"{value:.4f} {UNIT[joint_type]}"


def _pct(value: float | None) -> str:
    """A relative difference in per cent, or a dash where there is none."""
    return "–" if value is None else f"{100 * value:.2f} %"


def rows(prepared: dict) -> tuple[list[str], int, int, dict[str, float], int]:
    """Table rows of every pull, the passes, the total, the largest difference per kind
    (emulated, before the stop) and how many pulls as loaded miss the expected verdict."""
    lines, passed, total, worst, loaded_wrong = [], 0, 0, {}, 0
    for item in prepared.values():
        joint = item.joint
        for multiple in MULTIPLES:
            force = multiple * item.breakaway
            reference = mujoco_pull(item.mjcf, force, SECONDS)
            expected = "still" if multiple < 1 else "opens"
            runs = {m: sapien_pull(item, force, m, reference.timestep) for m in MODELS}
            result = compare_pull(
                reference, runs["emulated"], joint["type"], joint["range"][1], expected
            )
            loaded = compare_pull(
                reference, runs["as loaded"], joint["type"], joint["range"][1], expected
            )
            ok = result.passed
            loaded_wrong += loaded.pybullet_moved != expected
            passed, total = passed + ok, total + 1
            kind = item.config.base.kind
            if result.difference_then is not None:
                worst[kind] = max(worst.get(kind, 0.0), result.difference_then)
            lines.append(
                f"| {item.config.id} | {item.mode} | {multiple:g}× = {force:.2f} N | "
                f"{_q(result.mujoco, joint['type'])} | {_q(result.pybullet, joint['type'])} | "
                f"{result.compare_time:.3f} s: {_pct(result.difference_then)} | "
                f"{result.mujoco_moved} / {result.pybullet_moved} | "
                f"{_q(loaded.pybullet, joint['type'])} ({loaded.pybullet_moved}) | "
                f"{'pass' if ok else 'FAIL'} |"
            )
    return lines, passed, total, worst, loaded_wrong


def render(lines, passed, total, worst, loaded_wrong, command, cost) -> str:
    """The report."""
    head = (
        "| configuration | mode | pull | MuJoCo after 1 s | SAPIEN emulated after 1 s | "
        "before the stop: t, difference | verdicts MuJoCo / SAPIEN emulated | "
        "SAPIEN as loaded after 1 s | result |\n|---|---|---|---:|---:|---|---|---:|---|"
    )
    largest = ", ".join(f"{kind} {100 * v:.2f} %" for kind, v in worst.items())
    return f"""# The exported URDF in SAPIEN against MuJoCo: the pulls

Written by `{command}` ({cost}); SAPIEN {version("sapien")} (CPU PhysX, no renderer), MuJoCo
{version("mujoco")}. Method and reading: [the study's README](../README.md).

Verdicts and pass criteria as in [pybullet.md](pybullet.md): still = moved less than 1 mm / 2 mrad;
opens = at least the task's partial opening; pass = both give the expected verdict (0.5× still,
1.2× and 2× open) and, where the front moves, the openings agree within 10 % (after 1 s, or
before MuJoCo's front reaches half its range).

{head}
{chr(10).join(lines)}

**{passed} of {total} pulls pass with the friction emulated.** Largest relative difference of
the openings before the stop: {largest}. As loaded (last column), {loaded_wrong} of {total} pulls
miss the expected verdict.
"""


def main(argv=None) -> int:
    """Build and export the sample, pull it in both simulators and write the report."""
    warnings.filterwarnings("ignore", module="sapien")
    args = sample_arguments(__doc__.split("\n\n")[0], DEFAULT_OUT, argv)
    start, cpu = time.perf_counter(), time.process_time()
    settings, cache_root, _, sample = sample_context()
    lines, passed, total, worst, loaded_wrong = [], 0, 0, {}, 0
    with tempfile.TemporaryDirectory(prefix="realikea_sapien_") as scratch:
        work = args.work or Path(scratch)
        for mode in SAMPLE_MODES:
            prepared = prepare(sample, mode, ("coacd",), work, settings, cache_root)
            mode_lines, mode_passed, mode_total, mode_worst, mode_wrong = rows(prepared)
            lines += mode_lines
            loaded_wrong += mode_wrong
            passed, total = passed + mode_passed, total + mode_total
            for kind, value in mode_worst.items():
                worst[kind] = max(worst.get(kind, 0.0), value)
    cost = f"{time.perf_counter() - start:.0f} s wall, {time.process_time() - cpu:.0f} s CPU"
    command = "nice -n 10 python experiments/interop/sapien_check.py"
    args.out.write_text(render(lines, passed, total, worst, loaded_wrong, command, cost))
    print(f"wrote {args.out}: {passed} of {total} pulls pass ({cost})")
    return 0 if passed == total else 1


if __name__ == "__main__":
    sys.exit(main())
