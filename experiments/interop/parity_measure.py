"""PyBullet against MuJoCo on the exported sample, as data: the handle pulls, the fingertip
probe and the probe's clearances (parity_unexpressed.py: what PyBullet does not express)."""

from __future__ import annotations

from typing import NamedTuple

from realikea.interop import probe
from realikea.interop.parity import (
    SECONDS,
    ProbeParity,
    PullParity,
    compare_pull,
)
from realikea.interop.pull import Trajectory, mujoco_pull, pybullet_pull
from realikea.interop.sample import MULTIPLES, Prepared

STOP_TOLERANCE = 1e-3  # a front within this fraction of its range's upper end is at its stop


def pull_both(
    item: Prepared, force: float, timestep: float | None = None, **pybullet_options
) -> tuple[Trajectory, Trajectory]:
    """The same pull in MuJoCo (exported MJCF) and PyBullet (exported URDF), at the MJCF's
    timestep unless `timestep` is given."""
    joint = item.joint
    reference = mujoco_pull(item.mjcf, force, SECONDS, timestep)
    other = pybullet_pull(
        item.urdf,
        item.handle,
        joint["anchor"],
        joint["axis"],
        force,
        SECONDS,
        timestep=reference.timestep,
        **pybullet_options,
    )
    return reference, other


class Pull(NamedTuple):
    """One pull of check (a): the configuration, the force and both simulators' openings."""

    config_id: str
    kind: str
    category: str
    mode: str
    joint_type: str
    multiple: float
    force: float
    result: PullParity
    mujoco_stop: bool  # the front reached its joint's stop within the pull
    pybullet_stop: bool


def reached_stop(trajectory: Trajectory, upper: float) -> bool:
    """Whether a front reached its joint's stop within the pull."""
    return trajectory.time_to(upper - STOP_TOLERANCE * upper) is not None


def pulls(prepared: dict[tuple, Prepared]) -> list[Pull]:
    """Check (a) on every prepared configuration, at each multiple of its breakaway force."""
    found = []
    for item in prepared.values():
        jtype, upper = item.joint["type"], item.joint["range"][1]
        for multiple in MULTIPLES:
            force = multiple * item.breakaway
            reference, other = pull_both(item, force)
            result = compare_pull(
                reference, other, jtype, upper, "still" if multiple < 1 else "opens"
            )
            config = item.config
            found.append(
                Pull(config.id, config.base.kind, config.part.category, item.mode, jtype,
                     multiple, force, result, reached_stop(reference, upper),
                     reached_stop(other, upper))
            )  # fmt: skip
    return found


class ProbeRun(NamedTuple):
    """One run of check (b): the fingertip pushed through the gap behind a two-point bar."""

    config_id: str
    source: str
    pieces: int
    gap: float  # m
    result: ProbeParity


def probes(prepared: dict[tuple, Prepared]) -> list[ProbeRun]:
    """Check (b) on every prepared two-point configuration and collision source."""
    found = []
    for (config_id, source), item in sorted(prepared.items()):
        if item.config.part.category != "two_point":
            continue
        path = probe.ProbePath.from_metadata(item.metadata)
        pieces = probe.part_pieces(item.urdf)
        result = ProbeParity(
            "passes" if source == "coacd" else "blocked",
            path.through,
            probe.mujoco_probe(pieces, path),
            probe.pybullet_probe(item.urdf, path),
        )
        found.append(ProbeRun(config_id, source, len(pieces), path.gap, result))
    return found


class Clearance(NamedTuple):
    """The probe centred under the bar (CoACD): its distance to the part and to the front (m)."""

    config_id: str
    geometric: float  # gap / 2 less the probe's half thickness
    mujoco: float
    pybullet: float
    to_front: float  # PyBullet only


def clearances(prepared: dict[tuple, Prepared]) -> list[Clearance]:
    """The probe's clearances on every prepared two-point configuration's CoACD pieces."""
    found = []
    for (config_id, source), item in sorted(prepared.items()):
        if item.config.part.category != "two_point" or source != "coacd":
            continue
        path = probe.ProbePath.from_metadata(item.metadata)
        pieces = probe.part_pieces(item.urdf)
        to_part, to_front = probe.pybullet_clearance(item.urdf, path)
        geometric = path.gap / 2 - probe.PROBE_HALF[2]
        found.append(
            Clearance(config_id, geometric, probe.mujoco_clearance(pieces, path), to_part, to_front)
        )
    return found
