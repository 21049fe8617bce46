"""The exported URDFs in SAPIEN against the exported MJCFs in MuJoCo; writes results/sapien.md
(the table) and results/sapien_figures.json (the figures the README quotes).

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

import json
import re
import sys
import tempfile
import time
import warnings
from importlib.metadata import version
from pathlib import Path
from typing import NamedTuple

import numpy as np
from parity_report import opening, percent

from realikea.export.metadata import PART_LINK
from realikea.export.model import read_articulation
from realikea.files import atomic_write_text, repo_path
from realikea.interop.parity import SECONDS, PullParity, compare_pull
from realikea.interop.pull import Trajectory, mujoco_pull, opening_direction
from realikea.interop.sample import (
    MULTIPLES,
    SAMPLE_MODES,
    Prepared,
    prepare,
    sample_arguments,
    sample_context,
)
from realikea.markdown import table

DEFAULT_OUT = repo_path("experiments/interop/results/sapien.md")
BIG = 1e5  # drive damping of the emulated friction (N s/m, N m s/rad): a stiff velocity hold
MODELS = ("emulated", "as loaded")
COMMAND = "nice -n 10 python experiments/interop/sapien_check.py"


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


class SapienPull(NamedTuple):
    """One pull in MuJoCo and in SAPIEN, the friction emulated (`result`) and as loaded."""

    config_id: str
    mode: str
    kind: str
    joint_type: str
    multiple: float
    force: float
    result: PullParity
    loaded: PullParity


def pulls(prepared: dict) -> list[SapienPull]:
    """Every prepared configuration pulled at each multiple of its breakaway force."""
    found = []
    for item in prepared.values():
        joint = item.joint
        for multiple in MULTIPLES:
            force = multiple * item.breakaway
            reference = mujoco_pull(item.mjcf, force, SECONDS)
            expected = "still" if multiple < 1 else "opens"
            compared = {
                m: compare_pull(
                    reference, sapien_pull(item, force, m, reference.timestep), joint["type"],
                    joint["range"][1], expected,
                )
                for m in MODELS
            }  # fmt: skip
            found.append(
                SapienPull(item.config.id, item.mode, item.config.base.kind, joint["type"],
                           multiple, force, compared["emulated"], compared["as loaded"])
            )  # fmt: skip
    return found


def report(found: list[SapienPull], provenance: str) -> str:
    """results/sapien.md: the table, under the line that says how it was made."""
    rows = [
        [
            p.config_id, p.mode, f"{p.multiple:g}× = {p.force:.2f} N",
            opening(p.result.mujoco, p.joint_type), opening(p.result.pybullet, p.joint_type),
            f"{p.result.compare_time:.3f} s: {percent(p.result.difference_then)}",
            f"{p.result.mujoco_moved} / {p.result.pybullet_moved}",
            f"{opening(p.loaded.pybullet, p.joint_type)} ({p.loaded.pybullet_moved})",
            "pass" if p.result.passed else "FAIL",
        ]
        for p in found
    ]  # fmt: skip
    header = ["configuration", "mode", "pull", "MuJoCo after 1 s", "SAPIEN emulated after 1 s",
              "before the stop: t, difference", "verdicts MuJoCo / SAPIEN emulated",
              "SAPIEN as loaded after 1 s", "result"]  # fmt: skip
    lines = [
        "# The exported URDF in SAPIEN against MuJoCo: the pulls",
        "",
        f"{provenance} Method and reading: [the study's README](../README.md).",
        "",
        *table(header, "lllrrllrl", rows),
    ]
    return "\n".join(lines) + "\n"


def figures(found: list[SapienPull], made: dict) -> dict:
    """How many pulls pass (emulated), the largest difference before the stop per kind, and how
    many pulls as loaded miss the expected verdict."""
    moving = [p for p in found if p.result.difference_then is not None]
    return {
        **made,
        "passed": sum(p.result.passed for p in found),
        "total": len(found),
        "largest_before_stop": {
            kind: max(p.result.difference_then for p in moving if p.kind == kind)
            for kind in dict.fromkeys(p.kind for p in moving)
        },
        "loaded_missed": sum(p.loaded.pybullet_moved != p.loaded.expected for p in found),
    }


def main(argv=None) -> int:
    """Build and export the sample, pull it in both simulators and write the table and figures."""
    warnings.filterwarnings("ignore", module="sapien")
    args = sample_arguments(__doc__.split("\n\n")[0], DEFAULT_OUT, argv)
    start, cpu = time.perf_counter(), time.process_time()
    settings, cache_root, _, sample = sample_context()
    found = []
    with tempfile.TemporaryDirectory(prefix="realikea_sapien_") as scratch:
        work = args.work or Path(scratch)
        for mode in SAMPLE_MODES:
            found += pulls(prepare(sample, mode, ("coacd",), work, settings, cache_root))
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    versions = {"sapien": version("sapien"), "mujoco": version("mujoco")}
    provenance = (
        f"Written by `{COMMAND}` ({wall:.0f} s wall, {cpu:.0f} s CPU); SAPIEN "
        f"{versions['sapien']} (CPU PhysX, no renderer), MuJoCo {versions['mujoco']}."
    )
    made = {"command": COMMAND, "versions": versions, "wall_s": wall, "cpu_s": cpu}
    data = figures(found, made)
    atomic_write_text(args.out, report(found, provenance))
    figures_path = args.out.with_name(args.out.stem + "_figures.json")
    atomic_write_text(figures_path, json.dumps(data, indent=2, allow_nan=False) + "\n")
    print(f"wrote {args.out}: {data['passed']} of {data['total']} pulls pass ({wall:.0f} s wall)")
    return 0 if data["passed"] == data["total"] else 1


if __name__ == "__main__":
    sys.exit(main())
