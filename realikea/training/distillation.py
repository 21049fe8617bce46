"""Per-group teachers distilled into one student: DAgger with rsl-rl's `Distillation`, each env's
action label given by the teacher of its category x kind group (`distill.teachers`).

    python train.py pipeline=none 'distill.teachers={knob_door: RUN/model_599.pt, ...}'

Why: one PPO policy over the nine groups can lose a group it had learned while the others come
up, whereas single-group specialists learn their groups reliably; distilling specialists into
one student is how PartManip-style generalists are trained. The student acts (its own actions
drive the envs, DAgger), the teachers label every step, and the loss is the mean squared error
between the student's mean action and its env's teacher's (clipped as the env clips it). The
student is saved as an actor checkpoint like PPO's (`actor_state_dict`, same network), so
`realikea eval policy=checkpoint` loads it and a PPO run can start from it (`train.init_actor`).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import torch
from omegaconf import DictConfig, OmegaConf
from rsl_rl.algorithms import Distillation
from rsl_rl.models import MLPModel
from rsl_rl.storage import RolloutStorage
from tensordict import TensorDict
from torch import nn

from realikea.assets.catalog import GROUPS
from realikea.errors import RealIkeaError
from realikea.files import repo_path
from realikea.policies.checkpoint import CheckpointPolicy, load_saved, saved_layout
from realikea.tasks import observations
from realikea.tasks.open_task import ACTION_SIZE

ROUTED_DISTILLATION = "realikea.training.distillation:RoutedDistillation"
# how the student acts in its rollouts (`distill.student_acts`): on samples of its Gaussian (its
# std `distill.student_std`), or on its mean action, as every evaluation runs it
STUDENT_ACTS = ("sample", "mean")


def distilling(cfg: DictConfig) -> bool:
    """Whether the run distils teachers (`distill.teachers` given) instead of running PPO."""
    return bool((cfg.get("distill") or {}).get("teachers"))


def teacher_paths(cfg: DictConfig) -> dict[str, Path]:
    """`distill.teachers` as {group: checkpoint path}, as given (no file read)."""
    given = cfg.distill.teachers
    if not isinstance(given, DictConfig):
        raise RealIkeaError(
            f"distill.teachers={given!r}: use {{group: checkpoint, ...}}, e.g. "
            "'distill.teachers={knob_door: RUN/model_399.pt}'"
        )
    return {str(k): repo_path(str(v)) for k, v in OmegaConf.to_container(given).items()}


def check_teachers(cfg: DictConfig, draw_groups: list[str]) -> None:
    """Refuse `distill.teachers` (naming the input) when a group is unknown, a group of the
    run's draw has no teacher, a checkpoint is missing or unreadable, or a teacher observes or
    acts on another layout than the student; a `distill.student_acts` not in `STUDENT_ACTS`;
    and a `distill.student_std` that is not a number above 0."""
    if cfg.asset.get("follow_success") is not None:
        raise RealIkeaError(
            "distill.teachers: a distilled run keeps each env in its group; drop "
            "asset.follow_success"
        )
    acts = cfg.distill.get("student_acts", "sample")
    if acts not in STUDENT_ACTS:
        raise RealIkeaError(f"distill.student_acts={acts}: use one of {', '.join(STUDENT_ACTS)}")
    std = cfg.distill.student_std
    if isinstance(std, bool) or not isinstance(std, int | float) or std <= 0:
        raise RealIkeaError(f"distill.student_std={std!r}: use an action std above 0, e.g. 0.1")
    paths = teacher_paths(cfg)
    unknown = sorted(set(paths) - set(GROUPS))
    if unknown:
        raise RealIkeaError(
            f"distill.teachers: unknown group {', '.join(unknown)}; use {', '.join(GROUPS)}"
        )
    missing = sorted(set(draw_groups) - set(paths))
    if missing:
        raise RealIkeaError(
            f"distill.teachers: no teacher for {', '.join(missing)}, which this run's draw holds"
        )
    for group, path in paths.items():
        check_teacher(group, path)


def check_teacher(group: str, path: Path) -> None:
    """Refuse a teacher that is missing, unreadable, or trained on another observation layout
    or action size than the student's."""
    try:
        saved = load_saved(path)
        layout = saved_layout(path, saved)
    except RealIkeaError as err:
        raise RealIkeaError(f"distill.teachers.{group}: {err}") from err
    if layout != list(observations.LAYOUT):
        raise RealIkeaError(
            f"distill.teachers.{group}: {path} observes layout {layout}; the student observes "
            f"{list(observations.LAYOUT)}"
        )
    actions = saved["actor_state_dict"]["distribution.std_param"].numel()
    if actions != ACTION_SIZE:
        raise RealIkeaError(
            f"distill.teachers.{group}: {path} acts on {actions} actions; the student on "
            f"{ACTION_SIZE}"
        )


class RoutedTeacher(nn.Module):
    """The teachers as one module: each env's action is its group's teacher's mean action,
    clipped to [-1, 1] as the task clips every action (`OpenTask.apply_action`), so the label is
    what the env would execute. `route()` gives each env's teacher index; the teachers are
    frozen (eval mode, no grad)."""

    def __init__(self, actors: list[MLPModel], route: Callable[[], torch.Tensor]):
        super().__init__()
        self.actors = nn.ModuleList(actors)
        self.route = route
        self.requires_grad_(False)
        self.eval()

    def forward(self, obs: TensorDict) -> torch.Tensor:
        route = self.route()
        actions = torch.zeros(obs.batch_size[0], ACTION_SIZE, device=route.device)
        for k, actor in enumerate(self.actors):
            envs = route == k
            if envs.any():
                actions[envs] = actor(obs[envs])
        return actions.clamp_(-1.0, 1.0)

    # rsl-rl's recurrent-model interface; the teachers are feed-forward
    def reset(self, dones=None, hidden_state=None) -> None:
        pass

    def get_hidden_state(self) -> None:
        return None


def routed_teacher(teachers: dict[str, str], env_groups: list[str]) -> RoutedTeacher:
    """The teachers of `teachers` (group -> checkpoint; one checkpoint may serve several
    groups, loaded once), each env routed to its group's."""
    paths = sorted(set(teachers.values()))
    actors = [CheckpointPolicy(Path(p)).actor for p in paths]
    route = torch.tensor([paths.index(teachers[g]) for g in env_groups], dtype=torch.long)
    return RoutedTeacher(actors, lambda: route)


class RoutedDistillation(Distillation):
    """rsl-rl's `Distillation` with a `RoutedTeacher` (built from the train config's
    `teacher.checkpoints` and the env's `groups`), the student acting on samples or (the train
    config's `student_acts: mean`) on its mean action, and saved as an actor."""

    act_on_mean = False

    @staticmethod
    def construct_algorithm(obs: TensorDict, env, cfg: dict, device: str) -> RoutedDistillation:
        algorithm = {k: v for k, v in cfg["algorithm"].items() if k != "class_name"}
        student_cfg = {k: v for k, v in cfg["student"].items() if k != "class_name"}
        student = MLPModel(obs, cfg["obs_groups"], "student", env.num_actions, **student_cfg)
        teacher = routed_teacher(cfg["teacher"]["checkpoints"], env.groups)
        storage = RolloutStorage(
            "distillation", env.num_envs, cfg["num_steps_per_env"], obs, [env.num_actions], device
        )
        alg = RoutedDistillation(
            student, teacher, storage, device=device, **algorithm, multi_gpu_cfg=cfg["multi_gpu"]
        )
        alg.teacher_loaded = True  # the teachers come loaded from their checkpoints
        alg.act_on_mean = cfg.get("student_acts") == "mean"
        return alg

    def act(self, obs: TensorDict) -> torch.Tensor:
        """rsl-rl's step (the student's sample acted on, each env's teacher's action its label,
        the transition stored), with `act_on_mean` the mean of the distribution that sample
        came from acted on and stored instead (the runner logs that distribution's std)."""
        actions = super().act(obs)
        if self.act_on_mean:
            actions = self.transition.actions = self.student.output_mean.detach()
        return actions

    def save(self) -> dict:
        return {
            "actor_state_dict": self._raw_student.state_dict(),
            "optimizer_state_dict": self.optimizer.state_dict(),
        }

    def load(self, loaded_dict: dict, load_cfg: dict | None, strict: bool) -> bool:
        """Resume the student (and its optimizer) from its own checkpoint."""
        self._raw_student.load_state_dict(loaded_dict["actor_state_dict"], strict=strict)
        if "optimizer_state_dict" in loaded_dict:
            self.optimizer.load_state_dict(loaded_dict["optimizer_state_dict"])
        return True


def distillation_config(cfg: DictConfig, ppo: dict, teachers: dict[str, Path]) -> dict:
    """The rsl-rl train_cfg of a distilled run: PPO's (`ppo`, from `runner_config`) rollout,
    saving and logging, its actor network as the student (with `distill.student_std` as its
    action std, and `distill.student_acts`: whether it acts on samples or its mean), and
    `distill`'s optimisation settings."""
    distill = cfg.distill
    return {
        **{k: ppo[k] for k in ("num_steps_per_env", "save_interval", "logger", "check_for_nan")},
        "obs_groups": {"student": ["policy"], "teacher": ["policy"]},
        "algorithm": {
            "class_name": ROUTED_DISTILLATION,
            "learning_rate": float(distill.learning_rate),
            "num_learning_epochs": int(distill.num_learning_epochs),
            "gradient_length": int(distill.gradient_length),
            "max_grad_norm": float(ppo["algorithm"]["max_grad_norm"]),
            "loss_type": "mse",
        },
        "student": {
            **ppo["actor"],
            "distribution_cfg": {
                "class_name": "GaussianDistribution",
                "init_std": float(distill.student_std),
            },
        },
        "teacher": {"checkpoints": {group: str(path) for group, path in teachers.items()}},
        "student_acts": str(distill.get("student_acts", "sample")),
    }
