"""What PyBullet does not express, measured on the exported sample against MuJoCo: its joint
motor and the ignored URDF friction, its damping against a damping applied by hand, its body
damping, the time step, creep below breakaway and excursions past the joint limits."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

from parity_measure import pull_both

from realikea.assets.library import load_model
from realikea.interop.parity import SECONDS, comparison_time, relative_difference
from realikea.interop.pull import pybullet_pull
from realikea.interop.pybullet_sim import PYBULLET_BODY_DAMPING
from realikea.interop.sample import Prepared

FINE_STEP = 0.0005  # s: the finer step of the time-step check


class FrictionModels(NamedTuple):
    """Opening after 1 s under one pull, with PyBullet's joint friction three ways."""

    mujoco: float
    emulated: float  # PyBullet's motor capped at the URDF friction (what (a) uses)
    default: float  # PyBullet's motor as loaded
    ignored: float  # PyBullet's motor off


class DampingCheck(NamedTuple):
    """One 1.2x pull with PyBullet's damping three ways, and its body damping on and off."""

    config_id: str
    joint_type: str
    by_urdf: float  # after 1 s, <dynamics damping> applied by PyBullet
    by_hand: float  # after 1 s, the same damping applied as a joint force -c v
    difference: float  # the larger of the two at 1 s and before the stop
    undamped: float  # after 1 s, no damping
    then: float  # s: the comparison time before the stop
    mujoco_then: float
    undamped_body_then: float  # PyBullet with its body damping off (used)
    damped_body_then: float  # PyBullet with its default body damping
    undamped_body_difference: float
    damped_body_difference: float


class StepCheck(NamedTuple):
    """One 1.2x pull at 2 ms and at FINE_STEP, before the stop: relative differences."""

    config_id: str
    kind: str
    then: float
    coarse: float  # PyBullet vs MuJoCo at 2 ms
    fine: float  # PyBullet vs MuJoCo at FINE_STEP
    mujoco: float  # MuJoCo at 2 ms vs at FINE_STEP
    pybullet: float  # PyBullet at 2 ms vs at FINE_STEP


class Excursion(NamedTuple):
    """How far a 2x pull takes the front past its upper limit."""

    config_id: str
    kind: str
    joint_type: str
    upper: float
    mujoco: float
    pybullet: float


class Creep(NamedTuple):
    """Opening after 1 s at half the breakaway force."""

    config_id: str
    kind: str
    joint_type: str
    mujoco: float
    pybullet: float


@dataclass
class Unexpressed:
    """What PyBullet does not express, measured on one resistance mode's sample."""

    friction: list[tuple[str, str, float, FrictionModels]] = field(default_factory=list)
    damping: list[DampingCheck] = field(default_factory=list)
    steps: list[StepCheck] = field(default_factory=list)
    limits: list[Excursion] = field(default_factory=list)
    creep: list[Creep] = field(default_factory=list)
    hold: dict[float, float] = field(default_factory=dict)  # pull x step -> opening after 1 s
    hold_step: float = 0.0
    hold_id: str = ""
    largest_breakaway: float = 0.0


def unexpressed(prepared: dict[tuple, Prepared]) -> Unexpressed:
    """What PyBullet does not express, measured on the high-resistance sample."""
    found = Unexpressed()
    for item in prepared.values():
        cid, kind = item.config.id, item.config.base.kind
        jtype, upper = item.joint["type"], item.joint["range"][1]
        for multiple in (0.5, 2.0):
            force = multiple * item.breakaway
            reference, emulated = pull_both(item, force)
            default, ignored = (
                pull_both(item, force, friction=model)[1].at(SECONDS)
                for model in ("default", "ignored")
            )
            models = FrictionModels(reference.at(SECONDS), emulated.at(SECONDS), default, ignored)
            found.friction.append((cid, jtype, multiple, models))
            if multiple == 0.5:
                found.creep.append(Creep(cid, kind, jtype, models.mujoco, models.emulated))
            else:
                found.limits.append(
                    Excursion(cid, kind, jtype, upper, reference.q.max() - upper,
                              emulated.q.max() - upper)
                )  # fmt: skip
        force = 1.2 * item.breakaway
        _, by_urdf = pull_both(item, force)
        _, by_hand = pull_both(item, force, damping="manual")
        _, undamped = pull_both(item, force, damping="off")
        reference, body_damped = pull_both(item, force, body_damping=PYBULLET_BODY_DAMPING)
        t = comparison_time(reference, upper)
        found.damping.append(
            DampingCheck(
                cid, jtype, by_urdf.at(SECONDS), by_hand.at(SECONDS),
                max(relative_difference(by_urdf.at(s), by_hand.at(s)) for s in (t, SECONDS)),
                undamped.at(SECONDS), t, reference.at(t), by_urdf.at(t), body_damped.at(t),
                relative_difference(reference.at(t), by_urdf.at(t)),
                relative_difference(reference.at(t), body_damped.at(t)),
            )
        )  # fmt: skip
        if kind not in {s.kind for s in found.steps}:  # the same pull at a 4x finer step
            fine_mj, fine_pb = pull_both(item, force, timestep=FINE_STEP)
            found.steps.append(
                StepCheck(
                    cid, kind, t, relative_difference(reference.at(t), by_urdf.at(t)),
                    relative_difference(fine_mj.at(t), fine_pb.at(t)),
                    relative_difference(reference.at(t), fine_mj.at(t)),
                    relative_difference(by_urdf.at(t), fine_pb.at(t)),
                )
            )  # fmt: skip
    drawer = next(i for i in prepared.values() if i.joint["type"] == "slide")
    step = float(load_model(drawer.mjcf).opt.timestep)
    joint = drawer.joint
    found.hold = {
        scale: pybullet_pull(
            drawer.urdf, drawer.handle, joint["anchor"], joint["axis"], scale / step, SECONDS,
            timestep=step, friction="default",
        ).at(SECONDS)
        for scale in (0.9, 1.1)
    }  # fmt: skip
    found.hold_step = step
    found.hold_id = drawer.config.id
    found.largest_breakaway = max(i.breakaway for i in prepared.values())
    return found
