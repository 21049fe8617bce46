"""The potential variant: gated's stages and shaping paid as a potential's change, so no place
short of an opening pays a policy for staying there; on the formulas, and in the task with a
scripted hook."""

from __future__ import annotations

import dataclasses

import pytest

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.policies.registry import make_policy
from realikea.tasks.open_task import OpenTask
from realikea.tasks.rewards import VARIANTS, reward_from_config
from realikea.tasks.rewards.gated import next_stage
from realikea.tasks.rewards.potential import PotentialParams, potential
from realikea.tasks.rewards.terms import StepValues
from realikea.training.train import check_discount

P = PotentialParams()
POTENTIAL = VARIANTS["potential"]
GRASP = dict(d1=0.06, d2=0.01, aperture=0.3, straddle=True, engaged=True)


def scene(d1=0.3, d2=0.3, aperture=1.0, progress=0.0, straddle=False, engaged=False):
    """The values of a scene, its stage read as the gated variant reads it."""
    v = StepValues(
        1, d1, d2, aperture, progress * 0.2, progress, straddle, engaged,
        [0.0] * 5, [0.0] * 5, [0.0] * 5, True,
    )  # fmt: skip
    return dataclasses.replace(v, stage=next_stage(1, v, P))


def rewards(scenes: list[StepValues], terminal_last: bool = False) -> list[float]:
    """Each step's reward along `scenes` (the first is the reset), as the task pays it."""
    phi, grasped, out = potential(scenes[0], P), scenes[0].stage == 4, []
    for i, v in enumerate(scenes[1:], 1):
        grasped = grasped or v.stage == 4
        terminal = terminal_last and i == len(scenes) - 1
        v = dataclasses.replace(v, grasped=grasped, prev_potential=phi, terminal=terminal)
        out.append(sum(value for _, value in POTENTIAL.weighted_terms(v, P)))
        phi = potential(v, P)
    return out


def test_holding_any_stage_pays_no_more_than_nothing():
    """`gated` pays a held grasp about 0.4 a step; here every stage is no place to rest."""
    for where in (scene(), scene(d1=0.01, d2=0.06), scene(d2=0.01, aperture=0.3, straddle=True),
                  scene(**GRASP)):  # fmt: skip
        held = rewards([where] * 10)
        assert all(r <= 0.0 for r in held)
    assert scene(**GRASP).stage == 4


def test_reaching_a_stage_pays_its_premium_once():
    straddling, grasped = scene(d2=0.01, aperture=0.3, straddle=True), scene(**GRASP)
    (step,) = rewards([straddling, grasped])
    assert step == pytest.approx(
        P.scale * (P.gamma * potential(grasped, P) - potential(straddling, P))
    )
    assert step > P.scale * P.beta * 0.9


def test_a_slip_costs_the_premium_once_and_a_regrasp_earns_it_back():
    """Under `gated` a slip costs beta + hold every remaining step; here the path's discounted
    shaping telescopes to gamma^n Phi(end) - Phi(start), whatever happened between."""
    grasped, slipped = scene(**GRASP), scene(d1=0.06, d2=0.05, aperture=0.3)
    path = [grasped, slipped, slipped, grasped]
    shaping = sum(P.gamma**t * r for t, r in enumerate(rewards(path)))  # the discounted return
    assert shaping == pytest.approx(P.scale * (P.gamma**3 - 1.0) * potential(grasped, P))


def test_the_opening_pays_every_step_from_the_first_grasp_on_held_or_not():
    never = rewards([scene(d1=0.06, d2=0.05, aperture=0.3, progress=0.5)] * 2)[0]
    slipped = rewards([scene(**GRASP), *[scene(d1=0.06, d2=0.05, aperture=0.3, progress=0.5)] * 2])
    open_pay = P.scale * P.w_progress * 0.5
    assert never < 0.0 < open_pay - 0.01 < slipped[-1]
    held_open = rewards([scene(**GRASP, progress=1.0)] * 3)
    assert held_open[-1] > P.scale * (P.w_progress + P.success_bonus) - 0.01


def test_an_early_termination_ends_the_potential():
    """Phi = 0 after a termination (the shaping theorem's terminal state), so ending an
    episode early from a grasp costs what the grasp was worth."""
    (ended,) = rewards([scene(**GRASP), scene(**GRASP)], terminal_last=True)
    assert ended == pytest.approx(-P.scale * potential(scene(**GRASP), P), abs=0.02)


def test_gamma_is_checked_against_the_learner():
    with pytest.raises(RealIkeaError, match=r"gamma=1\.5"):
        reward_from_config({"variant": "potential", "gamma": 1.5})
    cfg = load_config(["task/reward=potential", "task.reward.gamma=0.98"])
    with pytest.raises(RealIkeaError, match="agent.algorithm.gamma=0.99"):
        check_discount(reward_from_config(dict(cfg.task.reward))[1], cfg)
    check_discount(reward_from_config(dict(load_config(["task/reward=potential"]).task.reward))[1],
                   load_config())  # fmt: skip


def test_the_task_keeps_the_potential_from_step_to_step(tmp_path):
    """In the kitchen: the hook oracle's episode under `potential` pays the shaping's telescoped
    sum plus the opening, and opens the drawer."""
    cfg = load_config(
        ["asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20", "dr=fixed",
         f"paths.library={tmp_path}", "task/reward=potential", "policy=hook_oracle"],
        "eval",
    )  # fmt: skip
    task = OpenTask(cfg, training_configurations(cfg, 1, 0)[0], seed=0)
    policy = make_policy(cfg)
    obs = task.reset()
    policy.reset([0], [task.facts()])
    start, phis = task.state.potential, []
    for _ in range(task.horizon):
        result = task.step(policy.act(obs[None])[0])
        obs = result.obs
        phis.append(task.state.potential)
        if result.terminated or result.truncated:
            break
    terms = result.info["reward_terms"]
    n = len(phis)
    expected = sum(P.gamma * phis[i] - (phis[i - 1] if i else start) for i in range(n))
    assert terms["shaping"] == pytest.approx(P.scale * expected)
    assert task.opening > 0.2 and terms["open"] > 10 * abs(terms["shaping"])
