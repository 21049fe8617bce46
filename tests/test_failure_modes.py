"""The failure modes of failed episodes: labels from constructed evidence, and the monitor's
evidence from small physical scenes (a pusher on a knob, a hand against a wall)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from realikea.eval.protocol import EvalResult
from realikea.tasks.contacts import ContactMonitor
from realikea.tasks.failure_modes import (
    FAILURE_KEYS,
    FAILURE_MODES,
    FailureLog,
    FailureMonitor,
    FailureParams,
    failure_mode,
)

P = FailureParams(
    carried_pull=3.0, lost_seconds=0.5, saturated=0.9, squeeze=2.0, reach=0.03,
    behind_pull=2.0, blocked_force=10.0, blocked_seconds=0.3, turn=0.15,
)  # fmt: skip
DT = 0.01  # s between samples


def _log(**kw) -> FailureLog:
    return FailureLog(samples=1000, **kw)


@pytest.mark.parametrize(
    ("log", "category", "mode"),
    [
        # a 30 N pinch lost 5 s before the end
        (_log(carried=30, last_carry=500, squeeze=5, touched=400, closest=0.0), "knob", "slip"),
        # a pinch still on at the end, its friction saturated: sliding
        (
            _log(carried=20, last_carry=999, last_saturation=0.99, squeeze=5, touched=900),
            "knob", "slip",
        ),
        # pushed, not pinched (no squeeze), then lost: the fingers never got behind the bar
        (
            _log(carried=6, last_carry=300, squeeze=0.2, touched=300, closest=0.003),
            "two_point", "narrow_clearance",
        ),
        # the hand pressed the neighbouring front for 0.5 s
        (_log(blocked=50, closest=0.2), "two_point", "mutual_interference"),
        # a slip next to the worktop is a slip
        (_log(carried=30, last_carry=500, squeeze=5, blocked=50, touched=400), "knob", "slip"),
        # touched a knob, never levered, wrist never turned
        (_log(touched=200, closest=0.01, turned=0.05), "knob", "specialized_design"),
        # turned the wrist at the lip, still never got under it
        (_log(touched=200, closest=0.05, turned=0.4), "finger_pull", "narrow_clearance"),
        # a hold to the end that opened too little
        (
            _log(carried=30, last_carry=999, last_saturation=0.3, squeeze=40, touched=900),
            "two_point", "other",
        ),
        # never reached the part
        (_log(closest=0.2), "two_point", "other"),
        # got behind, then lost it without a pinch
        (
            _log(carried=10, last_carry=200, behind=8, touched=200, closest=0.0),
            "two_point", "other",
        ),
    ],
)  # fmt: skip
def test_modes_from_constructed_evidence(log, category, mode):
    assert failure_mode(log, category, P, DT) == mode


def test_a_success_has_no_failure_mode_and_the_summary_keys_are_what_the_pool_passes_on():
    log = _log(carried=30, last_carry=500, squeeze=5, touched=400)
    assert log.summary("success", "knob", P, DT)["failure_mode"] is None
    summary = log.summary("partial", "knob", P, DT)
    assert summary["failure_mode"] == "slip" and tuple(summary) == FAILURE_KEYS


def test_eval_summary_counts_failure_modes_over_all_episodes():
    episodes = [
        {"outcome": "success", "strategy": "hook", "failure_mode": None},
        {"outcome": "fail", "strategy": "pinch", "failure_mode": "slip"},
        {"outcome": "partial", "strategy": "pinch", "failure_mode": "slip"},
        {"outcome": "fail", "strategy": "none", "failure_mode": "other"},
    ]
    modes = EvalResult(episodes).summary()["failure_modes"]
    assert tuple(modes) == FAILURE_MODES
    assert modes["slip"] == 0.5 and modes["other"] == 0.25
    assert sum(modes.values()) == pytest.approx(1 - 0.25)  # 1 - success


_SCENE = """
<mujoco>
  <option timestep="0.002" gravity="0 0 0"/>
  <worldbody>
    <geom name="wall" type="box" size="0.01 0.2 0.2" pos="0.3 0 0"/>
    <body name="front" pos="0 0 0">
      <joint name="slide" type="slide" axis="1 0 0" damping="5"/>
      <geom name="panel" type="box" size="0.01 0.2 0.2"/>
      <body name="part" pos="-0.03 0 0.1">
        <geom name="knob" type="box" size="0.01 0.01 0.01"/>
      </body>
    </body>
    <body name="hand" pos="{x} 0 0.1">
      <joint name="push" type="slide" axis="1 0 0" damping="50"/>
      <geom name="pad" type="box" size="0.02 0.02 0.02"/>
    </body>
  </worldbody>
  <actuator><motor joint="push" gear="20"/></actuator>
</mujoco>
"""


def _run(x: float) -> FailureLog:
    """The hand pushed along +x for 1 s from `x`: onto the knob (x < 0) or into the wall."""
    model = mujoco.MjModel.from_xml_string(_SCENE.format(x=x))
    data = mujoco.MjData(model)
    hand, knob, panel = model.body("hand").id, model.geom("knob").id, model.geom("panel").id
    contacts = ContactMonitor(model, [hand], [knob], [panel])
    failure = FailureMonitor(model, [model.geom("pad").id], [knob, panel])
    log, u = FailureLog(), np.array([1.0, 0.0, 0.0])
    data.ctrl[0] = 1.0
    for _ in range(100):
        mujoco.mj_step(model, data, nstep=5)
        found = contacts.forces(data)
        reach = abs(float(data.xpos[hand][0] - data.xpos[model.body("part").id][0]))
        failure.record(log, data, found, u, reach, 0.0, P)
    return log


def test_monitor_reads_a_push_behind_the_knob_as_normal_pull_without_squeeze():
    log = _run(-0.08)
    assert log.touched > 50 and log.behind > 10 and log.carried > 10
    assert log.squeeze == pytest.approx(0.0, abs=1e-6)  # one pad: nothing cancels
    assert log.blocked == 0  # the front is not the scene


def test_monitor_reads_pressing_the_wall_as_interference():
    log = _run(0.25)
    assert log.touched == 0 and log.blocked > 50
    assert failure_mode(log, "knob", P, DT) == "mutual_interference"
