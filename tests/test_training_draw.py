"""The stratified draw's turns over its groups: one each by default, more where weighted."""

from __future__ import annotations

import pytest

from realikea.assets.library import group_turns, training_draw
from realikea.config import load_config
from realikea.errors import RealIkeaError

LABELS = [("knob", "drawer"), ("knob", "door"), ("two_point", "door"), ("two_point", "flap")]


def test_without_weights_every_group_takes_one_turn_in_the_draw_order():
    assert group_turns(LABELS, None) == LABELS
    assert load_config([]).asset.group_weights is None  # the default draw is the unweighted one


def test_a_weighted_value_gives_its_groups_extra_turns_after_a_full_round():
    turns = group_turns(LABELS, {"door": 2})
    assert turns == LABELS + [("knob", "door"), ("two_point", "door")]


def test_a_label_weighs_the_product_of_its_values():
    turns = group_turns(LABELS, {"door": 2, "knob": 2})
    assert turns.count(("knob", "door")) == 4
    assert turns.count(("two_point", "door")) == turns.count(("knob", "drawer")) == 2
    assert turns.count(("two_point", "flap")) == 1


def test_a_group_named_whole_is_weighted_alone_and_with_its_values():
    turns = group_turns(LABELS, {"door": 2, "two_point_door": 2})
    assert turns.count(("two_point", "door")) == 4 and turns.count(("knob", "door")) == 2
    assert turns.count(("two_point", "flap")) == 1


@pytest.mark.parametrize(
    "weights", [{"doors": 2}, {"two_point_drawer": 2}, {"door": 1.5}, {"door": 0}, {"door": "2"}]
)
def test_a_weight_on_no_group_or_not_a_whole_number_is_refused_by_name(weights):
    with pytest.raises(RealIkeaError, match="asset.group_weights"):
        group_turns(LABELS, weights)


def test_a_hinge_side_keeps_only_the_doors_hinged_on_it():
    cfg = load_config(["asset=two_point", "asset.kind=door", "asset.hinge=left"])
    bases = {c.base.id for group in training_draw(cfg, 16).groups.values() for c in group}
    assert bases == {"door_left_w40_h80", "door_left_w60_h80"}


@pytest.mark.parametrize(
    ("overrides", "says"),
    [
        (["asset.kind=door", "asset.hinge=up"], "asset.hinge='up': use null, left or right"),
        (["asset.kind=drawer", "asset.hinge=left"], "kind=drawer hinge=left"),  # drawers: none
    ],
)
def test_a_hinge_side_that_is_none_or_keeps_no_door_is_refused_by_name(overrides, says):
    with pytest.raises(RealIkeaError, match=says):
        training_draw(load_config(["asset=two_point", *overrides]), 16)
