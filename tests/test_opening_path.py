"""Scripted pulls: the point the hand holds follows the front's arc, the hand keeps its offset."""

import numpy as np
import pytest

from realikea.policies.scripted import held_path, opening_path, rotated
from realikea.sim.ik import rolled_nominal
from realikea.tasks.facts import SceneFacts


def _door(turn: float) -> SceneFacts:
    """A left-hinged door (axis +z through y = -0.2) and the hand rolled so that its pitch axis
    is the hinge axis times `turn` (+1 or -1)."""
    nominal = rolled_nominal(turn * np.pi / 2)
    zero = np.zeros(3)
    return SceneFacts(
        "c", "p", "finger_pull", "door", "hinge", zero, zero, zero, np.eye(3),
        np.array([1.0, 0.0, 0.0]), np.array([0.0, -0.2, 0.7]),
        turn * nominal[:, 0], "mesh.obj", nominal,
    )  # fmt: skip


@pytest.mark.parametrize("turn", [1.0, -1.0])
def test_with_the_whole_turn_the_tcp_rides_its_own_arc(turn):
    facts = _door(turn)
    held, tcp = np.array([0.0, 0.14, 0.7]), np.array([0.03, 0.18, 0.7])
    path = held_path(opening_path(held, facts, 0.4, 1.2, 1.0), held, tcp, facts)
    for got, t in path:  # the hand turns by the front's angle, in the pitch's sense
        arm = rotated(tcp - facts.hinge_anchor, facts.hinge_axis, turn * t)
        np.testing.assert_allclose(got, facts.hinge_anchor + arm, atol=1e-12)


def test_with_the_wrist_held_the_hand_translates_with_the_held_point():
    facts = _door(1.0)
    held, tcp = np.array([0.0, 0.14, 0.7]), np.array([0.03, 0.18, 0.7])
    arc = opening_path(held, facts, 0.4, 1.2, 0.0)
    path = held_path(arc, held, tcp, facts)
    for (point, _), (got, turn) in zip(arc, path, strict=True):
        np.testing.assert_allclose(got - point, tcp - held, atol=1e-12)
        assert turn == 0.0
    assert np.linalg.norm(path[-1][0] - opening_path(tcp, facts, 0.4, 1.2, 0.0)[-1][0]) > 0.01


def test_rotated_turns_about_the_axis():
    np.testing.assert_allclose(
        rotated(np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0]), np.pi / 2), [0, 1, 0],
        atol=1e-12,
    )  # fmt: skip
