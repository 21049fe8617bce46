"""The gated reward variant against the appendix variant's traps: closed empty jaws at the handle,
a lost grasp, a knob wider than the jaws close to, partial openings; on the formulas and, for
the grasp gates, on scripted policies in the kitchen (pinch, hook, lever, a closed-jaws poke)."""

from __future__ import annotations

import dataclasses
import itertools
import math

import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.policies.registry import make_policy
from realikea.policies.rollout import episode
from realikea.policies.scripted import CLOSE, Waypoint, WaypointPolicy
from realikea.rewards import VARIANTS, reward_from_config, variant_name
from realikea.rewards.gated import GatedParams, next_stage
from realikea.rewards.terms import StepValues
from realikea.tasks.grip import straddle_offset
from realikea.tasks.open_task import OpenTask

P = GatedParams()
GATED = VARIANTS["gated"]


def values(
    stage=1, d1=0.3, d2=0.3, aperture=1.0, progress=0.0, straddle=False, engaged=False, push=0.0
):
    """A step at a steady opening (`prev_progress` = `progress`: the rate term pays nothing)."""
    return StepValues(
        stage, d1, d2, aperture, progress * 0.2, progress, straddle, engaged,
        [0.0] * 5, [0.0] * 5, [0.0] * 5, True, push=push, prev_progress=progress,
    )  # fmt: skip


def step_reward(**kwargs) -> tuple[int, float]:
    """(stage, reward) of a step from the scene values `kwargs`."""
    v = values(**kwargs)
    stage = next_stage(v.stage, v, P)
    v = values(**{**kwargs, "stage": stage})
    return stage, sum(value for _, value in GATED.weighted_terms(v, P))


@pytest.mark.parametrize("previous", [1, 2, 3, 4])
def test_closed_empty_jaws_at_the_handle_do_not_reach_stage_4(previous):
    """The appendix's 13-run trap: closed jaws within 2 cm of t2 latched stage 4."""
    stage, r = step_reward(stage=previous, d1=0.06, d2=0.0, aperture=0.0)
    assert stage == 2
    assert r < step_reward(d2=0.0, aperture=0.5, straddle=True, engaged=True)[1]


def test_a_lost_grasp_leaves_stage_4():
    held = step_reward(stage=4, d2=0.01, aperture=0.3, straddle=True, engaged=True)
    assert held[0] == 4
    assert step_reward(stage=4, d2=0.05, aperture=0.3)[0] == 2  # slipped off, still near
    assert step_reward(stage=4, d1=0.5, d2=0.5, aperture=0.3)[0] == 1  # the hand left
    assert step_reward(stage=4, d2=0.01, aperture=0.6, straddle=True)[0] == 3  # jaws opened


def test_each_stage_starts_at_or_above_the_previous_ones_maximum():
    """Each stage's least reward (over its region) against the one before's greatest."""
    far = 0.5
    top1 = step_reward(d1=P.tau1, d2=far, aperture=1.0)
    low2 = step_reward(d1=far, d2=P.refine_radius - 1e-9, aperture=0.0)
    top2 = step_reward(d1=0.0, d2=0.0, aperture=1.0)
    low3, top3 = (step_reward(d2=0.03, aperture=a, straddle=True) for a in (1.0, 0.0))
    low4 = step_reward(d2=0.05, aperture=1.0, engaged=True)
    assert [top1[0], low2[0], top2[0], low3[0], top3[0], low4[0]] == [1, 2, 2, 3, 3, 4]
    assert low2[1] >= top1[1] and low3[1] >= top2[1] - 1e-12 and low4[1] >= top3[1]


def test_a_partial_opening_earns_less_than_success_and_opening_pays_linearly():
    """The appendix's log(100 q + 1) paid more for the first 2 cm than for 10 -> 20 cm."""
    held = {q: step_reward(d2=0.01, aperture=0.3, engaged=True, progress=q)[1] for q in
            (0.0, 0.1, 0.5, 0.6, 0.99, 1.0, 1.5)}  # fmt: skip
    assert held[0.1] - held[0.0] == pytest.approx(held[0.6] - held[0.5])
    assert held[1.0] - held[0.99] > P.scale * P.success_bonus  # the bonus at the threshold
    assert held[1.5] == pytest.approx(held[1.0])  # nothing to gain past success
    # holding a partial opening (half-way) for the rest of an episode returns less than success
    assert 60 * held[0.5] < 60 * held[1.0] - 60 * P.scale * P.success_bonus


def test_a_step_held_at_success_pays_about_two():
    """Every term x scale: a step held at success (stage 4's baseline and hold, the opening,
    the bonus) pays about 2, so value targets stay under about 250 at gamma 0.99; the rate term
    adds, over a whole episode, at most scale x w_rate (12)."""
    best = step_reward(d2=0.0, aperture=0.3, engaged=True, progress=1.0)[1]
    assert 2.0 < best <= 2.3
    assert step_reward(d1=1.0, d2=1.0, aperture=0.0)[1] > -0.01


def test_straddle_is_between_the_inner_faces():
    left, right = [0.0, 0.0, 0.0], [0.0, 0.05, 0.0]
    assert straddle_offset(left, right, [0.0, 0.025, 0.01], 0.0045) < 0.02
    assert not straddle_offset(left, right, [0.0, 0.025, 0.03], 0.0045) < 0.02  # off the line
    assert not straddle_offset(left, right, [0.0, 0.003, 0.0], 0.0045) < 0.02  # inside a pad
    closed = [0.0, 0.009, 0.0]  # pad centres of closed jaws: the inner faces meet
    assert not straddle_offset(left, closed, [0.0, 0.0045, 0.0], 0.0045) < 0.02


def test_the_centre_term_pays_straddling_on_the_pads_line_and_never_outbids_a_grasp():
    """`w_center` (0 in the default recipe): in stage 3 jaws centred on the handle earn
    w_center more than jaws straddling it at the edge of the radius, and no straddle earns what
    a grasp does."""
    centred = GatedParams(w_center=5.0)

    def reward(offset: float, engaged: bool = False) -> tuple[int, float]:
        v = StepValues(
            3, 0.3, 0.01, 0.5, 0.0, 0.0, True, engaged, [0.0] * 5, [0.0] * 5, [0.0] * 5, True,
            offset,
        )  # fmt: skip
        v = dataclasses.replace(v, stage=next_stage(3, v, centred))
        return v.stage, sum(value for _, value in GATED.weighted_terms(v, centred))

    (stage_on, on_line), (stage_edge, at_edge) = reward(0.0), reward(centred.straddle_radius)
    assert stage_on == stage_edge == 3
    assert on_line - at_edge == pytest.approx(centred.scale * centred.w_center)
    assert reward(0.0, engaged=True)[1] > on_line
    assert P.w_center == 0.0
    with pytest.raises(RealIkeaError, match=r"w_close \+ w_center"):
        GatedParams(w_center=6.0)  # beta = 10 < 5 + 6


def test_the_stage_3_approach_pays_advancing_onto_t2_and_never_outbids_a_grasp_there():
    """`w_app3` (0 in the default recipe): straddling jaws earn more the nearer the hand is to
    the grasp target t2, and at every distance a grasp there earns more still."""
    advancing = GatedParams(w_app3=2.0)

    def reward(d2: float, engaged: bool = False, aperture: float = 0.0) -> tuple[int, float]:
        v = StepValues(
            3, 0.3, d2, aperture, 0.0, 0.0, True, engaged, [0.0] * 5, [0.0] * 5, [0.0] * 5, True,
        )  # fmt: skip
        v = dataclasses.replace(v, stage=next_stage(3, v, advancing))
        return v.stage, sum(value for _, value in GATED.weighted_terms(v, advancing))

    far, near = reward(0.02), reward(0.0)
    assert far[0] == near[0] == 3
    expected = advancing.scale * advancing.w_app3 * (math.log(0.02 + P.eps) - math.log(P.eps))
    assert near[1] - far[1] == pytest.approx(expected)
    for d2 in (0.0, 0.01, 0.02):
        assert reward(d2, engaged=True, aperture=1.0)[1] > reward(d2)[1]
    assert P.w_app3 == 0.0
    with pytest.raises(RealIkeaError, match=r"w_app3=3.0 must be <= w_hold=2.0"):
        GatedParams(w_app3=3.0)


def test_the_rate_term_pays_the_capped_openings_increase_where_the_opening_is_paid():
    """`w_rate` (1200 in the default recipe): a step pays the capped level's increase over it, only
    where the opening is paid (stage 4, or after a grasp with keep_opening), so an episode's
    sum is the capped opening made since, and closing the front costs what opening it paid."""
    rated = P

    def rate(stage: int, before: float, after: float, grasped: bool = True) -> float:
        v = dataclasses.replace(
            values(stage=stage, progress=after), prev_progress=before, grasped=grasped
        )
        return dict(GATED.weighted_terms(v, rated))["rate"]

    assert rate(4, 0.2, 0.3) == pytest.approx(rated.scale * rated.w_rate * 0.1)
    assert rate(4, 0.3, 0.2) == pytest.approx(-rated.scale * rated.w_rate * 0.1)
    assert rate(4, 0.9, 1.4) == pytest.approx(rated.scale * rated.w_rate * 0.1)  # capped at 1
    assert rate(2, 0.2, 0.3) == pytest.approx(rated.scale * rated.w_rate * 0.1)  # slipped
    assert rate(2, 0.2, 0.3, grasped=False) == 0.0  # never grasped: nothing paid
    assert dict(GATED.weighted_terms(values(stage=4, progress=0.5), P))["rate"] == 0.0  # steady


def test_open_target_pays_the_opening_past_the_threshold_up_to_it():
    """`open_target` (1 in the default recipe) caps the level and its rate: at 1.25 a front held
    at 1.2 x the threshold pays more than one held just past it, and the bonus is unchanged;
    a target below the threshold is refused."""
    margin = GatedParams(open_target=1.25)

    def terms(p: GatedParams, before: float, after: float) -> dict:
        v = dataclasses.replace(values(stage=4, progress=after), prev_progress=before)
        return dict(GATED.weighted_terms(v, p))

    assert terms(P, 1.0, 1.2)["open"] == terms(P, 1.0, 1.0)["open"]  # default: no pay past 1
    assert terms(P, 1.0, 1.2)["rate"] == 0.0
    past = terms(margin, 1.0, 1.2)
    assert past["open"] == pytest.approx(margin.scale * margin.w_progress * 1.2)
    assert past["rate"] == pytest.approx(margin.scale * margin.w_rate * 0.2)
    assert terms(margin, 1.2, 1.4)["rate"] == pytest.approx(margin.scale * margin.w_rate * 0.05)
    assert past["success"] == terms(P, 1.0, 1.2)["success"]
    with pytest.raises(RealIkeaError, match="open_target=0.9"):
        GatedParams(open_target=0.9)


def test_reopen_bonus_off_pays_open_jaws_only_before_the_first_grasp():
    """Default: stages 1 and 2 pay open jaws whether or not the episode has grasped. Off: a
    grasp lost with the jaws closed is not paid to open them, while the way in still is."""
    held = GatedParams(reopen_bonus=False)

    def approach(p: GatedParams, stage: int, aperture: float, grasped: bool) -> float:
        v = dataclasses.replace(values(stage=stage, aperture=aperture), grasped=grasped)
        return dict(GATED.weighted_terms(v, p))["approach"]

    for stage, weight in ((1, P.w_open1), (2, P.w_open2)):
        paid = P.scale * weight
        opened, closed = approach(P, stage, 1.0, True), approach(P, stage, 0.0, True)
        assert opened - closed == pytest.approx(paid)  # default: paid after a grasp too
        assert approach(held, stage, 1.0, True) == pytest.approx(closed)  # off: not after it
        assert approach(held, stage, 1.0, False) == pytest.approx(opened)  # the way in: paid


def test_an_episodes_rate_sum_is_the_opening_it_made_while_paid(library):
    """On the task: a pinch that opens the drawer earns, summed over the episode, the capped
    opening made from its grasp on (the level before it, a few mm at most, is not paid)."""
    steps = _episode(
        library, "tp_round_bar_128", "heuristic_pull", "policy=heuristic_pull",
        "task.reward.w_rate=100.0",
    )  # fmt: skip
    final = min(steps[-1]["progress"], 1.0)
    assert final > 0.5  # the scripted pinch opened the drawer
    paid = steps[-1]["terms"]["rate"] / (P.scale * 100.0)
    assert final - 0.05 < paid <= final + 1e-9


def test_pressing_the_closed_front_costs_in_proportion_up_to_push_force():
    """`w_push` (0 in the default recipe): a grasp pressed shut with 200 N pays less than
    straddling without pressing, so pressing cannot be a resting place."""
    pushing = GatedParams(w_push=40.0)
    grasp = dict(stage=4, d2=0.02, aperture=0.3, straddle=True, engaged=True)

    def reward(params, **kwargs) -> float:
        v = values(**kwargs)
        return sum(value for _, value in GATED.weighted_terms(v, params))

    assert reward(P, push=200.0, **grasp) == reward(P, **grasp)  # off by default
    cost = reward(pushing, **grasp) - reward(pushing, push=100.0, **grasp)
    assert cost == pytest.approx(pushing.scale * pushing.w_push * 100.0 / pushing.push_force)
    assert reward(pushing, push=2 * pushing.push_force, **grasp) == pytest.approx(
        reward(pushing, push=pushing.push_force, **grasp)
    )  # capped
    straddling = dict(stage=3, d2=0.02, aperture=0.3, straddle=True)
    assert reward(pushing, push=200.0, **grasp) < reward(pushing, **straddling)


def test_an_action_past_its_clip_costs_its_squared_excess():
    """`w_bound` (0 in the default recipe): the clip to [-1, 1] makes every sample of a mean
    far past it the same command; the cost pulls the mean back where exploring changes
    something."""
    bounded = GatedParams(w_bound=5.0)
    v = values(stage=2, d2=0.05)
    inside = sum(value for _, value in GATED.weighted_terms(v, bounded))
    past = sum(
        value for _, value in GATED.weighted_terms(dataclasses.replace(v, excess=4.0), bounded)
    )
    assert inside - past == pytest.approx(bounded.scale * bounded.w_bound * 4.0)
    assert P.w_bound == 0.0


def test_keep_opening_pays_an_opening_after_the_grasp_is_lost():
    """`keep_opening` (on in the default recipe): a pinch that slips on the way out keeps
    the opening it made; an episode that never grasped is paid nothing for an opening."""
    keep, dropped = P, GatedParams(keep_opening=False)
    slipped = values(stage=2, d2=0.05, progress=0.8)

    def opening_pay(params, v) -> float:
        return sum(value for name, value in GATED.weighted_terms(v, params) if name == "open")

    assert opening_pay(dropped, dataclasses.replace(slipped, grasped=True)) == 0.0
    assert opening_pay(keep, dataclasses.replace(slipped, grasped=True)) == pytest.approx(
        keep.scale * keep.w_progress * 0.8
    )
    assert opening_pay(keep, slipped) == 0.0  # never grasped


def test_a_pull_that_opens_5_cm_and_slips_pays_more_than_holding_still():
    """The default opening weights (w_progress 120, success_bonus 60, the reward screen's
    `gated_pull`) against the screen's first `gated_keep` ones (40, 20): the slip lands in
    stage 2 or 3 with 5 cm opened."""
    pull = P
    keep = GatedParams(w_progress=40.0, success_bonus=20.0, w_rate=0.0)
    held = values(stage=4, d2=0.01, aperture=0.3, straddle=True, engaged=True)
    slips = (
        values(stage=2, d1=0.06, d2=0.05, aperture=0.3, progress=0.25),
        values(stage=3, d2=0.02, aperture=0.3, straddle=True, progress=0.25),
    )

    def pay(params, v) -> float:
        return sum(value for _, value in GATED.weighted_terms(v, params))

    for slipped in (dataclasses.replace(v, grasped=True) for v in slips):
        assert next_stage(4, slipped, pull) == slipped.stage
        assert pay(pull, slipped) > pay(pull, held)
        assert pay(keep, slipped) < pay(keep, held)


def test_an_unknown_variant_is_refused_with_the_list_of_variants():
    with pytest.raises(RealIkeaError, match="use one of appendix, gated"):
        reward_from_config({"variant": "shaped"})
    with pytest.raises(RealIkeaError, match="Available options in 'task/reward'"):
        load_config(["task/reward=shaped"])
    with pytest.raises(RealIkeaError, match="kappa not a constant of the 'gated'"):
        reward_from_config({"variant": "gated", "kappa": 15.0})


def test_each_variants_config_is_its_params_defaults_and_refuses_other_keys():
    """The params dataclass is the one schema: `task/reward=<variant>` composes to its defaults,
    an override reaches the params, and a key it lacks is refused when composing."""
    for name, variant in VARIANTS.items():
        reward = load_config([f"task/reward={name}"]).task.reward
        assert dict(reward) == {"variant": name, **dataclasses.asdict(variant.params())}
    changed = load_config(["task.reward.w_close=3"]).task.reward
    assert reward_from_config(changed)[1] == GatedParams(w_close=3.0)
    with pytest.raises(RealIkeaError, match="w_nope"):
        load_config(["task.reward.w_nope=1"])


def test_a_config_naming_no_variant_is_the_appendix():
    """Checkpoints committed before variants carry a task.reward without `variant`."""
    assert variant_name({"w_open2": 0.0}) == "appendix"
    assert variant_name(load_config().task.reward) == "gated"
    assert math.isclose(GatedParams().hook_cos, math.cos(math.radians(70.0)))


class ClosedPoke(WaypointPolicy):
    """Closed jaws driven onto the handle point and held there: the appendix's empty stage 4."""

    name = "closed_poke"

    def plan(self, facts):
        normal = facts.part_rot[:, 2]  # out of the front
        return [
            Waypoint(facts.handle_pos + 0.08 * normal, 0.0, CLOSE, tolerance=0.01),
            Waypoint(facts.handle_pos, 0.0, CLOSE, tolerance=0.002, hold=60, timeout=60),
        ]


def _episode(library, part: str, policy, *overrides: str) -> list[dict]:
    """Per step: the stage, the aperture, the opening (also as progress), the force pressing
    the front shut and, at the episode's end, each reward term's sum, of one episode of
    `policy`."""
    cfg = load_config(
        [f"asset.part={part}", "asset.base=drawer_w60_h20", "dr=fixed", f"paths.library={library}",
         *overrides],
        "eval",
    )  # fmt: skip
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    policy = make_policy(cfg) if isinstance(policy, str) else policy
    return [
        {
            "stage": result.info["stage"],
            "aperture": task.aperture,
            "open": task.opening,
            "progress": task.state.progress,
            "push": task.pressing_force(),
            "terms": result.info.get("reward_terms"),
        }
        for result in episode(task, policy)
    ]


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    return tmp_path_factory.mktemp("library")


def test_the_task_reads_the_actions_excess_before_the_clip(library):
    cfg = load_config(
        ["asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20", "dr=fixed",
         f"paths.library={library}"],
        "eval",
    )  # fmt: skip
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    task.reset()
    task.step([0.0, 3.0, -1.5, 0.5, 0.0])
    assert task._step_values(2, [0.0] * 5, True).excess == pytest.approx(2.0**2 + 0.5**2)
    task.reset()
    assert task._step_values(1, [0.0] * 5, True).excess == 0.0


@pytest.mark.parametrize("part", ["tp_round_bar_128", "knob_mushroom_34"])
def test_a_closed_jaws_poke_reaches_stage_4_only_under_the_appendix(library, part):
    appendix = _episode(library, part, ClosedPoke(), "task/reward=appendix")
    gated = _episode(library, part, ClosedPoke())
    assert max(s["stage"] for s in appendix) == 4 and appendix[-1]["open"] < 0.01
    assert max(s["stage"] for s in gated) < 4
    assert max(s["push"] for s in gated) > 10.0  # closed jaws driven into the handle press it


@pytest.mark.parametrize(
    ("part", "policy", "aperture"),
    [
        ("knob_mushroom_34", "policy=heuristic_pull", (0.4, 1.01)),  # a pinch wider than 0.4
        ("tp_round_bar_128", "policy=hook_oracle", (0.0, 0.1)),  # a closed fist behind the bar
        ("knob_mushroom_34", "policy=hook_oracle", (0.9, 1.01)),  # open jaws behind the head
    ],
)
def test_pinches_hooks_and_levers_reach_stage_4_and_hold_it_while_opening(
    library, part, policy, aperture
):
    steps = _episode(library, part, policy.split("=")[1], policy)
    # the steps that move the front out, past the first 2 cm (the lever from below ends where
    # the arm's reach does, short of the drawer's stop, and lets go there)
    moved = [s for r, s in itertools.pairwise(steps) if s["open"] > r["open"] + 1e-4]
    opening = [s for s in moved if s["open"] > 0.02]
    assert opening and steps[-1]["open"] > 0.2  # the scripted policy opens the drawer
    # stage 4 while it opens (a hook may lose its contact for a step as the drawer hits its stop)
    assert sum(s["stage"] == 4 for s in opening) >= 0.9 * len(opening)
    assert all(aperture[0] <= s["aperture"] <= aperture[1] for s in opening)
    assert all(s["push"] == 0.0 for s in opening)  # off the closed stop nothing presses it
