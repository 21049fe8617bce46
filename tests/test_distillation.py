"""Per-group teachers distilled into one student: bad teachers refused before any work, each env
labelled by its own group's teacher, and a distilled run's checkpoint evaluated and fine-tuned
like a PPO actor."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import torch
from conftest import SMALL_RUN
from rsl_rl.models import MLPModel
from tensordict import TensorDict

from realikea.cli import main
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.policies.checkpoint import CheckpointPolicy, checkpoint_infos
from realikea.tasks import observations
from realikea.tasks.open_task import ACTION_SIZE
from realikea.training.distillation import (
    RoutedDistillation,
    RoutedTeacher,
    check_teachers,
    teacher_paths,
)
from realikea.training.train import check_inputs, init_actor, train, train_config

SMALL = [*SMALL_RUN, "agent.actor_hidden_dims=[8]", "agent.critic_hidden_dims=[8]"]
DOORS = ["knob_door", "two_point_door", "finger_pull_door"]


def actor(bias: float = 0.0, actions: int = ACTION_SIZE, size: int = observations.SIZE):
    """An actor with the small network whose mean action is `bias` everywhere."""
    obs = TensorDict({"policy": torch.zeros(1, size)}, batch_size=[1])
    model = MLPModel(
        obs,
        {"actor": ["policy"]},
        "actor",
        actions,
        hidden_dims=[8],
        activation="elu",
        obs_normalization=True,
        distribution_cfg={"class_name": "GaussianDistribution", "init_std": 1.0},
    )
    with torch.no_grad():
        model.mlp[-1].weight.zero_()
        model.mlp[-1].bias.fill_(bias)
    return model


def save_teacher(path, bias=0.0, actions=ACTION_SIZE, layout=None):
    """A checkpoint as a run of the small network saves it (its layout and config inside)."""
    infos = checkpoint_infos(load_config(SMALL))
    if layout is not None:
        infos["observation_layout"] = layout
    size = sum(n for _, n in layout) if layout else observations.SIZE
    state = actor(bias, actions, size).state_dict()
    torch.save({"actor_state_dict": state, "iter": 1, "infos": infos}, path)
    return path


def config(tmp_path, teachers: dict, *extra):
    teachers = "{" + ", ".join(f"{g}: {p}" for g, p in teachers.items()) + "}"
    return load_config([*SMALL, f"distill.teachers={teachers}", *extra])


def test_the_teachers_of_the_draws_groups_are_taken(tmp_path):
    good = save_teacher(tmp_path / "t.pt")
    cfg = config(tmp_path, {"two_point_drawer": good, "knob_door": good})
    check_teachers(cfg, ["two_point_drawer"])
    assert teacher_paths(cfg) == {
        "two_point_drawer": good,
        "knob_door": good,
    }


@pytest.mark.parametrize(
    ("teachers", "message"),
    [
        ({"two_point_drawers": "good"}, "unknown group two_point_drawers; use knob_drawer"),
        ({"knob_door": "good"}, "no teacher for two_point_drawer, which this run's draw holds"),
        ({"two_point_drawer": "missing"}, "teachers.two_point_drawer: checkpoint not found"),
        ({"two_point_drawer": "layout"}, "observes layout [('joints', 7)]; the student observes"),
        ({"two_point_drawer": "actions"}, "acts on 4 actions; the student on 5"),
    ],
)
def test_a_bad_teacher_is_refused_naming_it_before_any_work(tmp_path, teachers, message):
    files = {
        "good": save_teacher(tmp_path / "good.pt"),
        "layout": save_teacher(tmp_path / "layout.pt", layout=[["joints", 7]]),
        "actions": save_teacher(tmp_path / "actions.pt", actions=4),
        "missing": tmp_path / "missing.pt",
    }
    cfg = config(tmp_path, {g: files[name] for g, name in teachers.items()})
    with pytest.raises(RealIkeaError, match="distill.teachers") as err:
        check_inputs(cfg)  # what the preflight runs before Hydra writes the run folder
    assert message in str(err.value)


def test_teachers_not_given_as_a_mapping_are_refused():
    with pytest.raises(RealIkeaError, match=r"teachers='model.pt': use \{group: checkpoint"):
        check_inputs(load_config([*SMALL, "distill.teachers=model.pt"]))


def test_an_unknown_way_for_the_student_to_act_is_refused(tmp_path):
    good = save_teacher(tmp_path / "good.pt")
    cfg = config(tmp_path, {"two_point_drawer": good}, "distill.student_acts=greedy")
    with pytest.raises(RealIkeaError, match="student_acts=greedy: use one of sample, mean"):
        check_inputs(cfg)


@pytest.mark.parametrize("std", ["0", "-0.1", "wide", "true"])
def test_a_student_std_that_is_not_a_positive_number_is_refused(tmp_path, std):
    good = save_teacher(tmp_path / "good.pt")
    cfg = config(tmp_path, {"two_point_drawer": good}, f"distill.student_std={std}")
    with pytest.raises(RealIkeaError, match=r"student_std=.*: use an action std above 0"):
        check_inputs(cfg)


@pytest.mark.parametrize("acts", ["sample", "mean"])
def test_the_student_acts_on_samples_or_its_mean_and_is_labelled_by_its_teacher(tmp_path, acts):
    """One rollout step of the routed distillation: the envs step on the student's action (a
    sample of its std-1 Gaussian round its mean 0.25, or that mean), its teacher's is the label."""
    teacher = save_teacher(tmp_path / "t.pt", bias=-0.5)
    cfg = config(tmp_path, {"two_point_drawer": teacher}, f"distill.student_acts={acts}")
    train_cfg = train_config(cfg)
    train_cfg["student"]["distribution_cfg"]["init_std"] = 1.0
    train_cfg["multi_gpu"] = None  # as rsl-rl's runner sets it on one device
    obs = TensorDict({"policy": torch.randn(4, observations.SIZE)}, batch_size=[4])
    env = SimpleNamespace(num_envs=4, num_actions=ACTION_SIZE, groups=["two_point_drawer"] * 4)
    alg = RoutedDistillation.construct_algorithm(obs, env, train_cfg, "cpu")
    with torch.no_grad():
        alg.student.mlp[-1].weight.zero_()
        alg.student.mlp[-1].bias.fill_(0.25)
    actions = alg.act(obs)
    assert torch.equal(alg.transition.actions, actions)
    assert torch.equal(alg.transition.privileged_actions, torch.full((4, ACTION_SIZE), -0.5))
    on_mean = torch.equal(actions, torch.full((4, ACTION_SIZE), 0.25))
    assert on_mean == (acts == "mean")
    assert torch.equal(alg.get_policy().output_std, torch.ones(4, ACTION_SIZE))  # as logged


def test_a_success_following_draw_is_refused(tmp_path):
    good = save_teacher(tmp_path / "good.pt")
    cfg = config(
        tmp_path,
        {"two_point_drawer": good},
        "asset=all",
        "+asset.follow_success={every: 5, below: 0.5, weight: 2}",
    )
    with pytest.raises(RealIkeaError, match="drop asset.follow_success"):
        check_inputs(cfg)


def test_each_env_is_labelled_by_its_groups_teacher_clipped_to_the_action_bounds():
    route = torch.tensor([1, 0, 1, 1])
    teacher = RoutedTeacher([actor(0.25), actor(-3.0)], lambda: route)
    obs = TensorDict({"policy": torch.randn(4, observations.SIZE)}, batch_size=[4])
    labels = teacher(obs)
    np.testing.assert_array_equal(labels[:, 0].numpy(), [-1.0, 0.25, -1.0, -1.0])
    assert not any(p.requires_grad for p in teacher.parameters())


def test_init_actor_copies_the_actor_and_refuses_another_network(tmp_path):
    source = save_teacher(tmp_path / "t.pt", bias=0.5)
    policy = actor(0.0)
    init_actor(SimpleNamespace(alg=SimpleNamespace(get_policy=lambda: policy)), source)
    obs = TensorDict({"policy": torch.randn(3, observations.SIZE)}, batch_size=[3])
    assert torch.allclose(policy(obs), torch.full((3, ACTION_SIZE), 0.5))
    wider = MLPModel(
        obs[:1],
        {"actor": ["policy"]},
        "actor",
        ACTION_SIZE,
        hidden_dims=[16],
        distribution_cfg={"class_name": "GaussianDistribution", "init_std": 1.0},
    )
    with pytest.raises(RealIkeaError, match="does not match this run's network"):
        init_actor(SimpleNamespace(alg=SimpleNamespace(get_policy=lambda: wider)), source)


def test_init_actor_with_resume_is_refused(tmp_path):
    source = save_teacher(tmp_path / "t.pt")
    cfg = load_config([*SMALL, f"train.init_actor={source}", f"train.resume={source}"])
    with pytest.raises(RealIkeaError, match="a resumed run restores its own actor"):
        check_inputs(cfg)


@pytest.mark.parametrize("acts", ["sample", "mean"])
def test_a_distilled_run_evaluates_and_starts_a_ppo_run(tmp_path, capsys, acts):
    """Four iterations distilling a constant teacher, the student acting on samples or its mean,
    then its checkpoint through `realikea eval` and as the start of a PPO run (both trainings in
    this process)."""
    teacher = save_teacher(tmp_path / "teacher.pt", bias=0.5)
    library = tmp_path / "library"
    common = [*SMALL, "logger=none", "agent.num_steps_per_env=8", f"paths.library={library}"]
    distilled, tuned = tmp_path / "distilled", tmp_path / "tuned"  # Hydra's run folders
    distilled.mkdir(), tuned.mkdir()
    cfg = load_config(
        [
            *common,
            "agent.max_iterations=4",
            f"distill.teachers={{two_point_drawer: {teacher}}}",
            "distill.learning_rate=0.01",  # 5 gradient steps an iteration
            f"distill.student_acts={acts}",
        ]
    )
    assert train(cfg, distilled) == distilled / "model_3.pt"
    losses = [
        float(line.split(",")[2])
        for line in (distilled / "metrics.csv").read_text().splitlines()
        if ",Loss/behavior," in line
    ]
    assert len(losses) == 4 and losses[-1] < 0.5 * losses[0]  # the student nears the teacher
    student = CheckpointPolicy(distilled / "model_3.pt")
    assert student.run_cfg.distill.teachers.two_point_drawer == str(teacher)
    evaluation = [f"policy.path={distilled / 'model_3.pt'}", *SMALL, f"paths.library={library}"]
    assert main(["eval", *evaluation, "episodes=1"]) == 0
    capsys.readouterr()
    cfg = load_config(
        [*common, "agent.max_iterations=1", f"train.init_actor={distilled / 'model_3.pt'}"]
    )
    saved = torch.load(train(cfg, tuned), weights_only=False)
    assert {"actor_state_dict", "critic_state_dict"} <= set(saved)
