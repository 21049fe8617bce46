"""The antipodal grasp sampler: grasps on the visual mesh, grasp files, one pulled drawer."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
import trimesh

from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.protocol import run_episodes
from realikea.policies.grasp_files import save_grasp_file
from realikea.policies.grasp_sampler import GraspSampler
from realikea.policies.grasp_sampling import (
    SamplerParams,
    reachable_pitch,
    reference_rotation,
    sample_grasps,
)
from realikea.policies.registry import make_policy
from realikea.pool.env_pool import EnvPool
from realikea.sim.ik import tcp_rotation
from realikea.tasks.open_task import OpenTask

BASE = "drawer_w60_h20"
PARTS = {"two_point": "tp_round_bar_128", "knob": "knob_round_30", "finger_pull": "fp_lip_40"}
FAST = SamplerParams(samples=1500, clearance_points=6000)


def _overrides(library, part, *extra):
    return [
        f"asset.part={part}",
        f"asset.base={BASE}",
        "dr=randomized",
        "resistance=smooth",
        f"paths.library={library}",
        *extra,
    ]


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    return tmp_path_factory.mktemp("library")


@pytest.fixture(scope="module")
def facts(library):
    """Scene facts of one randomized episode per category (part pose perturbed)."""
    out = {}
    for category, part in PARTS.items():
        cfg = load_config(_overrides(library, part))
        (mjcf,) = training_configurations(cfg, 1)
        task = OpenTask(cfg, mjcf, seed=1)
        task.iteration = 10**6  # randomization active
        task.reset()
        out[category] = task.facts()
    return out


@pytest.mark.parametrize("category", list(PARTS))
def test_grasps_are_antipodal_reachable_and_fit_the_aperture(facts, category):
    f = facts[category]
    reference = reference_rotation(f)
    grasps = sample_grasps(f.visual_mesh, reference, f.pad_friction, f.max_aperture, FAST)
    assert len(grasps) >= 5
    mesh = trimesh.load(f.visual_mesh, force="mesh")
    cone = math.atan(f.pad_friction)
    scores = [g.score for g in grasps]
    assert scores == sorted(scores, reverse=True)
    for g in grasps:
        rotation = g.pose[:3, :3]
        assert np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-9)
        pitch = reachable_pitch(rotation, reference, FAST.max_pitch, 1e-6)
        assert pitch is not None and abs(pitch) <= FAST.max_pitch + 1e-9
        first, second = g.contacts
        width = np.linalg.norm(second - first)
        assert FAST.min_width <= width <= f.max_aperture - 2 * FAST.clearance
        axis = (second - first) / width
        assert abs(axis @ rotation[:, 1]) == pytest.approx(1.0, abs=1e-6)  # the jaw axis
        # both outward normals within the friction cone of the squeeze
        _, _, tris = mesh.nearest.on_surface(g.contacts)
        n1, n2 = mesh.face_normals[tris]
        assert math.acos(np.clip(n1 @ -axis, -1, 1)) < cone + 1e-6
        assert math.acos(np.clip(n2 @ axis, -1, 1)) < cone + 1e-6
        assert 0.0 < g.margin <= cone and g.clearance >= FAST.clearance
        # the TCP is midway between the contacts, the contacts on the pads
        local = (g.contacts - g.pose[:3, 3]) @ rotation
        assert np.allclose(local[:, 0], 0.0, atol=1e-6) and np.all(np.abs(local[:, 2]) < 0.009)
        assert local[:, 1].sum() == pytest.approx(0.0, abs=1e-6)


def test_sampling_is_deterministic_for_a_seed(facts):
    f = facts["two_point"]
    reference = reference_rotation(f)
    runs = [sample_grasps(f.visual_mesh, reference, 1.0, 0.08, FAST) for _ in range(2)]
    other = sample_grasps(f.visual_mesh, reference, 1.0, 0.08, replace(FAST, seed=7))
    assert len(runs[0]) == len(runs[1])
    for a, b in zip(*runs, strict=True):
        assert np.array_equal(a.pose, b.pose) and a.score == b.score
    assert not np.array_equal(runs[0][0].contacts, other[0].contacts)


def test_the_plan_moves_the_part_frame_grasp_with_the_randomized_pose(facts):
    f = facts["two_point"]
    policy = GraspSampler(params=FAST)
    policy.reset([0], [f])
    best = policy.grasps(f)[0]
    assert policy.last_grasp is best
    plan = policy.plans[0]
    assert np.allclose(plan[1].pos, f.to_world(best.pose[:3, 3]))
    assert np.allclose(plan[-2].pos, plan[1].pos)  # close where the grasp is
    pull = plan[-1].pos - plan[1].pos
    assert np.allclose(pull, FAST.pull_distance * f.pull_dir)
    approach = tcp_rotation(plan[1].pitch, f.tcp_nominal)[:, 2]
    assert np.allclose(plan[1].pos - plan[0].pos, FAST.pregrasp * approach)


def test_grasp_file_round_trip(facts, tmp_path):
    f = facts["two_point"]
    sampled = GraspSampler(params=FAST)
    poses = np.stack([g.pose for g in sampled.grasps(f)[:3]])
    for name, write in (
        ("grasps.json", lambda p: save_grasp_file(p, {f.part_id: poses})),
        ("list.json", lambda p: save_grasp_file(p, {None: poses})),
        ("grasps.npy", lambda p: np.save(p, poses)),
        ("grasps.npz", lambda p: np.savez(p, **{f.part_id: poses})),
    ):
        path = tmp_path / name
        write(path)
        policy = GraspSampler(params=FAST, grasps=path)
        loaded = policy.grasps(f)
        assert np.allclose(np.stack([g.pose for g in loaded]), poses)
        policy.reset([0], [f])
        sampled.reset([0], [f])
        assert np.allclose(policy.plans[0][1].pos, sampled.plans[0][1].pos)
    # position + quaternion (w x y z), as 7-vectors and as JSON objects, through the config
    rotation = poses[0][:3, :3]
    quat = trimesh.transformations.quaternion_from_matrix(poses[0])  # w x y z
    assert np.allclose(trimesh.transformations.quaternion_matrix(quat)[:3, :3], rotation)
    np.save(tmp_path / "seven.npy", np.concatenate([poses[0][:3, 3], quat])[None])
    item = {"position": poses[0][:3, 3].tolist(), "quaternion": quat.tolist()}
    (tmp_path / "objects.json").write_text(json.dumps({f.part_id: [item]}))
    for name in ("seven.npy", "objects.json"):
        cfg = load_config(["policy=grasp_sampler", f"policy.grasps={tmp_path / name}"])
        policy = make_policy(cfg)
        assert isinstance(policy, GraspSampler)
        assert np.allclose(policy.grasps(f)[0].pose, poses[0], atol=1e-9)


def _bad(tmp_path, name, content):
    path = tmp_path / name
    if isinstance(content, np.ndarray):
        np.save(path, content)
    else:
        path.write_text(json.dumps(content))
    return path


def test_malformed_grasp_files_name_the_file_and_the_problem(facts, tmp_path):
    f = facts["two_point"]
    good = np.stack([g.pose for g in GraspSampler(params=FAST).grasps(f)[:2]])
    not_finite = good.copy()
    not_finite[0, 0, 3] = np.nan
    skewed = good.copy()
    skewed[1, :3, :3] *= 1.1
    cases = {
        "shape.npy": (np.zeros((2, 3, 3)), "shape"),
        "shape.json": ([[1.0, 2.0, 3.0]], "shape"),
        "nan.npy": (not_finite, "non-finite"),
        "skewed.json": (skewed.tolist(), "orthonormal"),
        "unknown.json": ({"no_such_part": good.tolist()}, "unknown part id"),
        "garbage.json": ({f.part_id: "abc"}, "list"),
    }
    for name, (content, problem) in cases.items():
        path = _bad(tmp_path, name, content)
        with pytest.raises(RealIkeaError, match=problem) as error:
            GraspSampler(grasps=path)
        assert str(path) in str(error.value)
    with pytest.raises(RealIkeaError, match="does not exist"):
        GraspSampler(grasps=tmp_path / "missing.json")
    # unreachable: the jaws turned 90 deg about the approach (roll fixed), or tipped too far
    turned = good.copy()
    turned[0, :3, :3] = good[0, :3, :3] @ np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    tipped = good.copy()
    tipped[1, :3, :3] = tcp_rotation(1.2, reference_rotation(f))
    for name, poses in (("turned.npy", turned), ("tipped.npy", tipped)):
        path = _bad(tmp_path, name, poses)
        policy = GraspSampler(params=FAST, grasps=path)
        with pytest.raises(RealIkeaError, match="cannot reach") as error:
            policy.reset([0], [f])
        assert str(path) in str(error.value)
    # a per-part file without the episode's part
    path = _bad(tmp_path, "other.json", {PARTS["knob"]: good.tolist()})
    with pytest.raises(RealIkeaError, match="no grasps for part"):
        GraspSampler(grasps=path).reset([0], [f])


def test_a_sampled_grasp_opens_a_smooth_two_point_drawer(library):
    overrides = [
        *_overrides(library, PARTS["two_point"]),
        "policy=grasp_sampler",
        "policy.samples=1500",
        "policy.clearance_points=6000",
        "contacts.log=true",
        "env.num_envs=1",
        "env.num_workers=0",
        "logger=none",
    ]
    cfg = load_config(overrides, "eval")
    policy = make_policy(cfg)
    with EnvPool.from_config(cfg) as pool:
        result = run_episodes(pool, policy, 1, progress=False)
    (episode,) = result.episodes
    assert episode["outcome"] == "success", episode
    assert episode["strategy"] == "pinch"
