"""The strategy classifier against scripted policies whose strategy is known by construction.

`hook_oracle` opens by form closure (a loop of fingertips behind a two-point bar, a wedge behind
a knob's head), `heuristic_pull` by a pinch. Episodes run in-process on the env pool with pose
randomization on and the contact log enabled, as `realikea eval` runs them.
"""

from __future__ import annotations

from realikea.config import load_config
from realikea.eval.protocol import run_episodes
from realikea.policies.registry import make_policy
from realikea.pool.env_pool import EnvPool

# (part, base): drawers, one per family with an undercut, sizes spread over the catalog
TWO_POINT = [
    ("tp_round_bar_128", "drawer_w40_h20"),
    ("tp_flat_bar_192", "drawer_w60_h40"),
    ("tp_d_handle_64", "drawer_w80_h20"),
    ("tp_u_handle_96", "drawer_w80_h40"),
]
KNOBS = [("knob_round_20", "drawer_w40_h20"), ("knob_mushroom_30", "drawer_w60_h20")]


def _episodes(policy: str, part: str, base: str, n: int, *extra: str) -> list[dict]:
    # the classifier is validated where the strategies are known to be executable: freestanding,
    # no neighbouring board in the way (in the kitchen a knob wedge from above on a top drawer
    # met the worktop: interference the kitchen tests and tables count, not a labelling question)
    cfg = load_config(
        [
            "scene=freestanding",
            f"policy={policy}",
            f"asset.part={part}",
            f"asset.base={base}",
            "dr=randomized",
            "contacts.log=true",
            "env.num_envs=2",
            "env.num_workers=0",
            *extra,
        ],
        "eval",
    )
    with EnvPool.from_config(cfg) as pool:
        return run_episodes(pool, make_policy(cfg), n, progress=False).episodes


def _agreement(episodes: list[dict], label: str) -> float:
    return sum(e.get("strategy") == label for e in episodes) / len(episodes)


def test_classifier_agrees_with_scripted_strategies():
    """hook on two-point bars and lever on knobs for hook_oracle, pinch for heuristic_pull."""
    cases = [("hook_oracle", p, b, "hook") for p, b in TWO_POINT]
    cases += [("hook_oracle", p, b, "lever") for p, b in KNOBS]
    cases += [("heuristic_pull", p, b, "pinch") for p, b in TWO_POINT[:3]]
    agree, total, misses = 0, 0, []
    for policy, part, base, label in cases:
        episodes = _episodes(policy, part, base, 4, "resistance=normal")
        hits = [e.get("strategy") == label for e in episodes]
        agree, total = agree + sum(hits), total + len(hits)
        misses += [
            (policy, part, e.get("strategy")) for e, h in zip(episodes, hits, strict=True) if not h
        ]
    assert total >= 36
    assert agree / total >= 0.95, misses


def test_hook_oracle_holds_two_point_drawers_in_high_resistance():
    """Form closure does not depend on friction: it opens in high resistance with elliptic and
    pyramidal cones (a pinch creeps under pyramidal ones). Menagerie's servo (0.3 N squeeze) is
    left out: a round bar caught off-centre can wedge its jaws open (see the policy's notes)."""
    part, base = TWO_POINT[0]
    for gripper in ("franka_hand",):
        for contact in ("elliptic", "pyramidal"):
            episodes = _episodes(
                "hook_oracle",
                part,
                base,
                2,
                "resistance=high",
                f"gripper={gripper}",
                f"contact={contact}",
            )
            outcomes = [e["outcome"] for e in episodes]
            assert outcomes == ["success"] * len(episodes), (gripper, contact, episodes)
            assert _agreement(episodes, "hook") == 1.0, (gripper, contact, episodes)
