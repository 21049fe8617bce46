"""`realikea eval ... record=DIR`: the evaluated episodes, step by step, as a LeRobotDataset v3.0.

Any policy the eval runs (scripted, checkpoint, replay) is stepped on the usual env pool with
`RecordingTask`s, so the episodes, and the printed table, are the evaluation's own. Each frame
holds the observation before the action (`observation.state`, the task's layout), the action,
then what followed it: `next.reward`, `next.done`, `next.opening` (the front's joint: m or rad)
and `contact.forces` (N, the control step's mean of the contact monitor's samples: the gripper's
normal and friction force along the opening direction on the part and on the front off it, and
its grip; `contacts.SAMPLE_FORCES`). The episodes table adds to lerobot's columns the
configuration (id, part, base, category, kind, collision source, resistance, gripper, contact),
the policy, the env and its seed, whether the policy saw the door mirrored (`task.mirror_doors`;
the frames are the world's either way, `realikea/tasks/recording.py`), and the labels:
`outcome`, `termination`, `strategy`, `failure_mode` (null for a success) with the classifier's
and the failure modes' evidence.

A teleoperated demonstration has no contact forces in its file: `record_demonstration` replays
it (bit for bit, `policy=replay`) and records the replay.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from omegaconf import DictConfig

from realikea.datasets.lerobot import Episode, check_target, write_dataset
from realikea.errors import RealIkeaError
from realikea.eval.protocol import EvalResult
from realikea.eval.setup import eval_setup, evaluate
from realikea.files import repo_path
from realikea.tasks import observations
from realikea.tasks.contacts import SAMPLE_FORCES, SUMMARY_KEYS
from realikea.tasks.failure_modes import FAILURE_KEYS
from realikea.tasks.open_task import ACTION_SIZE
from realikea.tasks.recording import EpisodeSteps, RecordingTask

ROBOT_TYPE = "panda"
ACTION_NAMES = ("pitch", "dx", "dy", "dz", "gripper")  # a0 .. a4 (docs/evaluation.md)
# the words an instruction uses for a part's category
PART_WORDS = {"knob": "knob", "two_point": "two-point handle", "finger_pull": "finger pull"}
# what the episodes table keeps of an episode's record, beside the configuration
RECORD_LABELS = (
    "env", "env_seed", "mirrored", "outcome", "termination", "opening", "episode_return",
    "episode_steps", *SUMMARY_KEYS, *FAILURE_KEYS, "policy_note",
)  # fmt: skip


def recording_target(cfg: DictConfig) -> Path | None:
    """The folder `record=` names (relative to the repository), checked before any episode runs;
    None without `record`."""
    if not cfg.get("record"):
        return None
    return check_target(repo_path(cfg.record))


def features() -> dict:
    """The per-frame features of a recorded episode (lerobot's `features` argument)."""
    state = [
        name if size == 1 else f"{name}.{k}"
        for name, size in observations.LAYOUT
        for k in range(size)
    ]
    return {
        "observation.state": {"dtype": "float32", "shape": [len(state)], "names": state},
        "action": {"dtype": "float32", "shape": [ACTION_SIZE], "names": list(ACTION_NAMES)},
        "next.reward": {"dtype": "float32", "shape": [1], "names": None},
        "next.done": {"dtype": "bool", "shape": [1], "names": None},
        "next.opening": {"dtype": "float32", "shape": [1], "names": None},
        "contact.forces": {
            "dtype": "float32", "shape": [len(SAMPLE_FORCES)], "names": list(SAMPLE_FORCES),
        },
    }  # fmt: skip


def instruction(category: str, kind: str) -> str:
    """The task of an episode in words, e.g. "open the drawer by its two-point handle"."""
    return f"open the {kind} by its {PART_WORDS[category]}"


def fps(cfg: DictConfig) -> int:
    """Frames per second: the control rate, which must be a whole number for lerobot."""
    rate = 1.0 / (int(cfg.task.decimation) * float(cfg.sim.timestep))
    if abs(rate - round(rate)) > 1e-6:
        raise RealIkeaError(
            f"a control rate of {rate:g} Hz (task.decimation x sim.timestep): a LeRobot dataset "
            "needs a whole number of frames per second"
        )
    return round(rate)


def to_episode(record: dict, cfg: DictConfig) -> Episode:
    """One pool episode record of a `RecordingTask` as a LeRobot episode."""
    steps: EpisodeSteps = record["steps"]
    done = np.zeros(steps.length, dtype=bool)
    done[-1] = True
    frames = {
        "observation.state": steps.observations,
        "action": steps.actions,
        "next.reward": steps.rewards,
        "next.done": done,
        "next.opening": steps.openings,
        "contact.forces": steps.contact_forces,
    }
    part, _, base = record["config_id"].partition("__")
    labels = {
        "config_id": record["config_id"],
        "part": part,
        "base": base,
        "category": record["category"],
        "kind": record["kind"],
        "collision": cfg.collision.source,
        "resistance": cfg.resistance.name,
        "gripper": cfg.gripper.name,
        "contact": cfg.contact.name,
        "policy": cfg.policy.name,
        **{key: record.get(key) for key in RECORD_LABELS},
    }
    return Episode(frames, instruction(record["category"], record["kind"]), labels)


def write_recording(result: EvalResult, cfg: DictConfig, target: Path) -> Path:
    """Write the episodes of `result` that carry their steps to the dataset folder `target`;
    the pool's cut-short episodes (divergence, a lost worker) have none and are counted."""
    recorded = [e for e in result.episodes if "steps" in e]
    if len(recorded) < len(result.episodes):
        print(f"not recorded: {len(result.episodes) - len(recorded)} episode(s) cut short")
    if not recorded:
        raise RealIkeaError(f"no episode to record in {target}: every episode was cut short")
    episodes = [to_episode(e, cfg) for e in recorded]
    return write_dataset(target, episodes, features(), fps(cfg), ROBOT_TYPE)


def record_demonstration(demonstration: Path, target: Path, library: str) -> Path:
    """A teleoperated demonstration as a LeRobot dataset: replayed through the eval on the asset
    library `library` (its recorded configuration, seed and physics), recorded."""
    overrides = ["policy=replay", f"policy.path={demonstration}", f"paths.library={library}"]
    cfg, replay = eval_setup(overrides)
    result = evaluate(cfg, replay, task_factory=RecordingTask)
    return write_recording(result, cfg, target)
