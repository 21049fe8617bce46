"""One policy for a draw over several category x kind groups, trained in stages
(`pipeline=distilled`, realikea/conf/pipeline/distilled.yaml): a teacher per kind, a group's own
teacher where the pipeline names one or its kind's teacher missed it (and, with
`pipeline.retrain_own`, a named one again on the next seed where it missed, with
`pipeline.learned_retrain_below` a teacher-rule one on the seed after its own; with
`pipeline.fine_tune`, its kind's teacher trained on to a group it left short), then every group's
teacher (with `pipeline.best_teacher`, the one of its teachers with the highest success on it)
distilled into one student, the launch's one checkpoint (with `pipeline.student_more`, read on
its small parts and trained on in the run folder, the groups it reads short weighted). A
teacher's success on a group, which
every rule reads, is its training success over its last full window, or with `pipeline.judge:
validation` that of its mean action on the validation draw (realikea/training/validation.py);
`pipeline.learned_judge` reads the teacher rule (a kind's teacher below `pipeline.learned`) on
its own measure.

    python train.py pipeline=distilled                     # RUN/teacher_*/, then RUN/model_199.pt
    python train.py pipeline=distilled_pairs               # the teachers two at a time
    python train.py pipeline=distilled train.resume=RUN    # continue a stopped one in RUN

Why: one PPO policy over the nine groups learns some groups and loses others by seed, whereas
specialists learn their groups reliably (experiments/generalist/README.md, the screen's rounds).
Each stage is a training run of the launch's own overrides with the pipeline's on top
(`stage_config`), in a folder of the run directory named after it; the student trains in the run
directory itself, so its metrics.csv and checkpoints are the launch's. A stage whose last
checkpoint is there is done; a stopped one continues from its last checkpoint. RUN/stages.json
records each finished stage: its overrides, the wall seconds of the launch that finished it and
each group's training success over its last full window (`realikea.training.metrics`).

A teacher is ready once the stage it needs is done (a kind's teacher-rule teachers, and a named
group teacher that starts from its kind's actor, `from_kind`, need that kind's teacher, a
retrained one the group's first; the others nothing), and of the ready ones
the longest starts first, so that it does not end the pipeline alone; among equal ones a
group's own teacher goes before a kind's, so that a retrain it may need starts while other
teachers still run. With `pipeline.stages_at_once` above 1 the teachers train that
many at a time, each in its own process with `pipeline.side_by_side` on top (one env worker each
on two cores); with `pipeline.alone_all_workers`, a teacher that starts with none running and
none ready trains alone to its end, so it takes the launch's workers instead. The student
trains last, alone, in the launch's own process.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import shutil
import signal
import time
from dataclasses import asdict, dataclass, replace
from multiprocessing.connection import wait
from pathlib import Path

from omegaconf import DictConfig, OmegaConf

from realikea.assets.catalog import (
    BASE_KINDS,
    CATEGORIES,
    GROUPS,
    group_name,
    kind_and_category,
)
from realikea.config import load_config, override_key, overrides_set
from realikea.errors import RealIkeaError
from realikea.eval.sweep import checkpoints
from realikea.files import CONF_DIR, atomic_write_text
from realikea.sim.resistance import MODES as RESISTANCE_MODES
from realikea.training.metrics import last_window
from realikea.training.queue import STAGES
from realikea.training.train import check_inputs, env_groups, train
from realikea.training.validation import (
    SMALL_PART_SIDES,
    small_part_reads,
    validation_success,
)

# the pipeline configs, realikea/conf/pipeline/<name>.yaml
PIPELINES = tuple(sorted(path.stem for path in (CONF_DIR / "pipeline").glob("*.yaml")))
# launch overrides no stage takes: the pipeline's own keys, its resume folder and its evaluation
LAUNCH_ONLY = ("pipeline", "train.resume", "train.eval_after")
# launch overrides a pipeline refuses (its stages set them, or a teacher must not take them) ->
# the settings to use instead
STAGE_SET = {
    "agent.max_iterations": "pipeline.teacher.iterations, pipeline.student.iterations, ...",
    "dr.switch_iteration": "pipeline.teacher.switch_iteration, ...",
    "distill.teachers": "pipeline=none to distil the teachers given in one run",
}
STUDENT = "student"
# the student trained on past `student.iterations` (`pipeline.student_more`), in the run folder too
STUDENT_MORE = "student_more"
# the keys a stage sets itself, which its own overrides (a group teacher's, the student's) may not
STAGE_KEYS = ("asset", "asset.kind", "env.seed", *STAGE_SET)
RETRAIN = "_retrain"  # the suffix of a group's own teacher trained again (`pipeline.retrain_own`)
FINE_TUNED = "_fine_tuned"  # the suffix of a kind teacher trained on one group (`fine_tune`)
# how a teacher's success on a group is read (`pipeline.judge`): its last training window, or its
# mean action on the validation draw
JUDGES = ("training", "validation")


@dataclass(frozen=True)
class Stage:
    """One training run of the pipeline: its name (its folder under the run directory; the
    student's is the run directory), its overrides on top of the launch's, its length, and the
    kind and category it teaches (a kind's teacher: no category; the student: neither)."""

    name: str
    overrides: tuple[str, ...]
    iterations: int
    kind: str = ""
    category: str = ""
    # the stage whose last checkpoint's actor this one starts from (`train.init_actor`), if any
    starts_from: str = ""


def pipelined(cfg: DictConfig) -> bool:
    """Whether the launch trains in stages (`pipeline.name` other than none)."""
    return str(OmegaConf.select(cfg, "pipeline.name", default="none")) != "none"


def check_pipeline(cfg: DictConfig) -> None:
    """Refuse a pipeline config that is unknown, names an unknown group, gives a group teacher
    or the student an override its stage sets itself or holds a length or mark out of range,
    naming the key."""
    pipeline, own = cfg.pipeline, own_teachers(cfg)
    if pipeline.name not in PIPELINES:
        raise RealIkeaError(f"pipeline={pipeline.name}: use one of {', '.join(PIPELINES)}")
    unknown = sorted(set(own) - set(GROUPS))
    if unknown:
        raise RealIkeaError(
            f"pipeline.own_teachers: unknown group {', '.join(unknown)}; use {', '.join(GROUPS)}"
        )
    specs = {key: pipeline[key] for key in ("teacher", "student", "fine_tune")}
    specs |= {f"own_teachers[{g}]": s for g, s in own.items()}
    specs |= {f"own_teachers[{g}].retrain": retrain_spec(s) for g, s in own.items()}
    for key, spec in specs.items():
        set_by_stage = [o for o in spec.get("overrides") or [] if stage_override_refused(str(o))]
        if set_by_stage:
            raise RealIkeaError(
                f"pipeline.{key}.overrides: {', '.join(map(str, set_by_stage))}; "
                f"use key=value overrides of keys other than {', '.join(STAGE_KEYS)}"
            )
        if not isinstance(spec.get("from_kind", False), bool):
            raise RealIkeaError(f"pipeline.{key}.from_kind={spec.from_kind}: use true or false")
        if int(spec.iterations) < 1 or not 0 <= int(spec.switch_iteration) <= int(spec.iterations):
            raise RealIkeaError(
                f"pipeline.{key}: iterations={spec.iterations}, switch_iteration="
                f"{spec.switch_iteration}; use iterations >= 1 and 0 <= switch_iteration <= "
                "iterations"
            )
    for group, spec in own.items():
        mark = spec.get("retrain_below", 0.0)
        if not is_rate(mark):
            raise RealIkeaError(
                f"pipeline.own_teachers[{group}].retrain_below={mark}: use a rate in [0, 1]"
            )
    check_student_more(cfg)
    for key in ("learned", "fine_tune.below"):
        rate = OmegaConf.select(pipeline, key)
        if not is_rate(rate):
            raise RealIkeaError(f"pipeline.{key}={rate}: use a rate in [0, 1]")
    mark = pipeline.learned_retrain_below
    if mark is not None and not is_rate(mark):
        raise RealIkeaError(
            f"pipeline.learned_retrain_below={mark}: use null (never) or a rate in [0, 1]"
        )
    bools = ("retrain_own", "alone_all_workers", "best_teacher", "keep_better_retrain",
             "own_after_fine_tune")  # fmt: skip
    for key in bools:
        if not isinstance(pipeline[key], bool):
            raise RealIkeaError(f"pipeline.{key}={pipeline[key]}: use true or false")
    if int(pipeline.stages_at_once) < 1:
        raise RealIkeaError(f"pipeline.stages_at_once={pipeline.stages_at_once}: use 1 or more")
    check_judging(cfg)


def check_judging(cfg: DictConfig) -> None:
    """Refuse a way of reading teachers that is unknown or out of range (`pipeline.judge`,
    `learned_judge`, `judge_resistances`, `judge_small_parts`, `validation_episodes`), or small-part
    reads under a draw pinned to a part, base or hinge side, naming the key."""
    pipeline = cfg.pipeline
    if pipeline.judge not in JUDGES:
        raise RealIkeaError(f"pipeline.judge={pipeline.judge}: use one of {', '.join(JUDGES)}")
    if pipeline.learned_judge not in (None, *JUDGES):
        raise RealIkeaError(
            f"pipeline.learned_judge={pipeline.learned_judge}: use null (as pipeline.judge) or "
            f"one of {', '.join(JUDGES)}"
        )
    modes = pipeline.judge_resistances
    if not OmegaConf.is_list(modes) or any(str(m) not in RESISTANCE_MODES for m in modes):
        raise RealIkeaError(
            f"pipeline.judge_resistances={modes}: use a list of modes of "
            f"{', '.join(RESISTANCE_MODES)}"
        )
    if modes and "validation" not in (pipeline.judge, learned_judge(cfg)):
        raise RealIkeaError(
            f"pipeline.judge_resistances={list(modes)} with pipeline.judge={pipeline.judge}: "
            "the modes are read on the validation draw; set pipeline.judge=validation or "
            "judge_resistances=[]"
        )
    small = pipeline.judge_small_parts
    if not OmegaConf.is_list(small) or any(str(c) not in CATEGORIES for c in small):
        raise RealIkeaError(
            f"pipeline.judge_small_parts={small}: use a list of categories of "
            f"{', '.join(CATEGORIES)}"
        )
    if small and pipeline.judge != "validation":
        raise RealIkeaError(
            f"pipeline.judge_small_parts={list(small)} with pipeline.judge={pipeline.judge}: "
            "the small parts are read on the validation draw; set pipeline.judge=validation or "
            "judge_small_parts=[]"
        )
    pinned = [k for k in ("part", "base", "hinge") if OmegaConf.select(cfg, f"asset.{k}")]
    if small and pinned:
        raise RealIkeaError(
            f"pipeline.judge_small_parts={list(small)} with asset.{pinned[0]} pinned: the "
            "small-part reads draw each family's smallest part on every base of a side"
        )
    episodes = pipeline.validation_episodes
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise RealIkeaError(f"pipeline.validation_episodes={episodes}: use a whole number >= 1")


def check_student_more(cfg: DictConfig) -> None:
    """Refuse a `pipeline.student_more` that is not null or {iterations, below, weight} in range,
    or that has no small-part reads to act on, naming the key."""
    more = cfg.pipeline.student_more
    if more is None:
        return
    keys = ("iterations", "below", "weight")
    if not OmegaConf.is_dict(more) or set(more) != set(keys):
        raise RealIkeaError(
            f"pipeline.student_more={more}: use null or {{iterations: N, below: RATE, weight: W}}"
        )
    for key in ("iterations", "weight"):
        value = more[key]
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise RealIkeaError(f"pipeline.student_more.{key}={value}: use a whole number >= 1")
    if not is_rate(more.below):
        raise RealIkeaError(f"pipeline.student_more.below={more.below}: use a rate in [0, 1]")
    if not cfg.pipeline.judge_small_parts:
        raise RealIkeaError(
            "pipeline.student_more with judge_small_parts=[]: the student is read on the "
            "small-part reads of those categories; name at least one"
        )


def is_rate(value: object) -> bool:
    """Whether a setting is a number in [0, 1] (true and false are not)."""
    return not isinstance(value, bool) and isinstance(value, int | float) and 0.0 <= value <= 1.0


def final_iterations(cfg: DictConfig) -> int:
    """The length of the launch's run whose checkpoints are in its run folder: the student's
    for a pipeline (with `student_more`'s iterations), the agent's otherwise."""
    if not pipelined(cfg):
        return int(cfg.agent.max_iterations)
    more = cfg.pipeline.student_more
    return int(cfg.pipeline.student.iterations) + (int(more.iterations) if more else 0)


def own_teachers(cfg: DictConfig) -> dict[str, DictConfig]:
    """`pipeline.own_teachers` by group."""
    return {str(entry.group): entry for entry in cfg.pipeline.own_teachers or []}


def from_kind(cfg: DictConfig, group: str) -> bool:
    """Whether the group's named teacher (and its retrain) starts from its kind's teacher."""
    named = own_teachers(cfg).get(group)
    return bool(named is not None and named.get("from_kind", False))


def judged_modes(cfg: DictConfig) -> list[str]:
    """The resistance modes a teacher is read in on the validation draw: the launch's own ("")
    and each of `pipeline.judge_resistances` other than it."""
    own = str(cfg.resistance.name)
    return ["", *(str(m) for m in cfg.pipeline.judge_resistances if str(m) != own)]


def learned_judge(cfg: DictConfig) -> str:
    """How the teacher rule reads a kind teacher's success (`pipeline.learned_judge`, else
    `pipeline.judge`)."""
    return str(cfg.pipeline.learned_judge or cfg.pipeline.judge)


def retrain_spec(named: DictConfig) -> DictConfig:
    """A named group teacher's retrain: its settings with its `retrain` ones on top."""
    spec = OmegaConf.masked_copy(named, [k for k in named if k != "retrain"])
    return OmegaConf.merge(spec, named.get("retrain") or {})


def retrain_mark(cfg: DictConfig, group: str) -> float:
    """The success (`pipeline.judge`) under which the group's named teacher trains again
    (`retrain_below`, else `pipeline.learned`)."""
    return float(own_teachers(cfg)[group].get("retrain_below", cfg.pipeline.learned))


def stage_override_refused(override: str) -> bool:
    """Whether a stage's own override (a group teacher's, the student's) is not `key=value`
    or sets a key every teacher stage sets itself."""
    return "=" not in override or override_key(override) in STAGE_KEYS


def teacher_stage(cfg: DictConfig, kind: str, category: str = "", retrain: bool = False) -> Stage:
    """The teacher of one kind's groups, or (`category`) a group's own teacher: on the launch's
    seed where the pipeline names it, else (its kind's teacher missed it, or `retrain`: the
    named one did, with its `retrain` settings) on the next seed, and a teacher-rule one's
    retrain on the seed after that; a named one with `from_kind` starts from the actor of its
    kind's teacher."""
    seed = int(cfg.env.seed)
    group = group_name(category, kind) if category else ""
    named = own_teachers(cfg).get(group)
    if named is not None and retrain:
        named = retrain_spec(named)
    trained_on = seed + 1 if category and (named is None or retrain) else seed
    if category and retrain and named is None:  # its first, by the teacher rule, on seed + 1
        trained_on = seed + 2
    return spec_stage(
        cfg,
        f"teacher_{group or kind}{RETRAIN if retrain else ''}",
        named or cfg.pipeline.teacher,
        kind,
        category,
        trained_on,
        teacher_stage(cfg, kind).name if named and named.get("from_kind", False) else "",
    )


def fine_tune_stage(cfg: DictConfig, kind: str, category: str) -> Stage:
    """A group's fine-tune (`pipeline.fine_tune`): its kind's teacher's last actor trained on
    the group alone, on the launch's seed."""
    return spec_stage(
        cfg,
        f"teacher_{group_name(category, kind)}{FINE_TUNED}",
        cfg.pipeline.fine_tune,
        kind,
        category,
        int(cfg.env.seed),
        teacher_stage(cfg, kind).name,
    )


def spec_stage(
    cfg: DictConfig,
    name: str,
    spec: DictConfig,
    kind: str,
    category: str,
    seed: int,
    starts_from: str,
) -> Stage:
    """A teacher stage on one kind (and category) and seed, as long as `spec` says, with its
    switch iteration and overrides, and `pipeline.side_by_side` when teachers train at once."""
    pipeline = cfg.pipeline
    own = tuple(str(o) for o in spec.get("overrides") or [])
    scope = (f"asset={category}",) if category else ()
    beside = tuple(pipeline.side_by_side) if int(pipeline.stages_at_once) > 1 else ()
    return Stage(
        name,
        (*scope, f"asset.kind={kind}", f"env.seed={seed}",
         f"agent.max_iterations={spec.iterations}", f"dr.switch_iteration={spec.switch_iteration}",
         *own, *beside),
        int(spec.iterations),
        kind,
        category,
        starts_from,
    )  # fmt: skip


def fine_tuned(cfg: DictConfig, group: str, rate: float) -> bool:
    """Whether a group its kind's teacher left at `rate` (at or above `pipeline.learned`) gets
    a fine-tune: it has no named teacher and `rate` is below `pipeline.fine_tune.below`."""
    return group not in own_teachers(cfg) and rate < float(cfg.pipeline.fine_tune.below)


def kind_teacher_stages(cfg: DictConfig, groups: list[str] | set[str]) -> list[Stage]:
    """The teacher of each kind with a group among `groups`."""
    return [teacher_stage(cfg, kind) for kind in BASE_KINDS
            if any(group_name(c, kind) in groups for c in CATEGORIES)]  # fmt: skip


def student_stage(cfg: DictConfig) -> Stage:
    spec = cfg.pipeline.student
    return Stage(
        STUDENT,
        (f"env.seed={int(cfg.env.seed)}", f"agent.max_iterations={spec.iterations}",
         f"dr.switch_iteration={spec.switch_iteration}",
         *(str(o) for o in spec.get("overrides") or [])),
        int(spec.iterations),
    )  # fmt: skip


def student_more_stage(cfg: DictConfig, launch: list[str], weak: list[str]) -> Stage:
    """The student trained on in the run folder to its `student.iterations` plus
    `student_more.iterations`, its draw giving each group of `weak` `student_more.weight` times
    the turns the student's own draw gives it."""
    student, more = student_stage(cfg), cfg.pipeline.student_more
    own = OmegaConf.select(stage_config(cfg, launch, student), "asset.group_weights") or {}
    weights = {str(k): int(v) for k, v in own.items()}
    weights |= {g: weights.get(g, 1) * int(more.weight) for g in weak}
    listed = ", ".join(f"{k}: {v}" for k, v in weights.items())
    replaced = ("agent.max_iterations", "asset.group_weights")
    return Stage(
        STUDENT_MORE,
        (*(o for o in student.overrides if override_key(o) not in replaced),
         f"agent.max_iterations={final_iterations(cfg)}",
         *([f"asset.group_weights={{{listed}}}"] if weights else [])),
        final_iterations(cfg),
    )  # fmt: skip


def judged_small_part_reads(cfg: DictConfig, group: str) -> list[str]:
    """The small-part reads a group is judged on: its own (`small_part_reads`) when its
    category is one of `pipeline.judge_small_parts`, else none."""
    small = {str(c) for c in cfg.pipeline.judge_small_parts}
    return small_part_reads(group) if kind_and_category(group)[1] in small else []


def student_read_groups(cfg: DictConfig, groups: list[str]) -> list[str]:
    """The draw's groups the student is read on before `student_more`: those judged on a
    small-part read (`judged_small_part_reads`)."""
    return [g for g in groups if judged_small_part_reads(cfg, g)]


def stage_config(
    cfg: DictConfig, launch: list[str], stage: Stage, teachers: dict[str, Path] | None = None
) -> DictConfig:
    """The stage's config: the launch's overrides (but `LAUNCH_ONLY`), the pipeline's
    `every_stage`, then the stage's, as one run (`pipeline=none`); the student's teachers as
    `distill.teachers`."""
    kept = [o for o in launch if not any(overrides_set([o], key) for key in LAUNCH_ONLY)]
    stage_cfg = load_config([*kept, *cfg.pipeline.every_stage, *stage.overrides, "pipeline=none"])
    if teachers:
        paths = {group: str(path) for group, path in teachers.items()}
        OmegaConf.update(stage_cfg, "distill.teachers", paths, merge=False)
    return stage_cfg


def check_stages(cfg: DictConfig, launch: list[str]) -> list[str]:
    """Check every stage the launch may train (`check_inputs`): the student without its
    teachers, the kind teachers, each group's own teacher (named, or by the teacher rule), a
    named one's retrain and an unnamed one's fine-tune; returns the student's draw's groups in
    `GROUPS` order."""
    check_pipeline(cfg)
    groups = set(env_groups(check_inputs(stage_config(cfg, launch, student_stage(cfg)))))
    stages = kind_teacher_stages(cfg, groups)
    for group in sorted(groups):
        scope = kind_and_category(group)
        stages.append(teacher_stage(cfg, *scope))
        if group in own_teachers(cfg) and cfg.pipeline.retrain_own:
            stages.append(teacher_stage(cfg, *scope, retrain=True))
        if fine_tuned(cfg, group, float(cfg.pipeline.learned)):
            stages.append(fine_tune_stage(cfg, *scope))
    more = cfg.pipeline.student_more
    if more is not None:  # every group it may weigh (none under a mark of 0), weighed at once
        weighable = student_read_groups(cfg, sorted(groups)) if float(more.below) > 0 else []
        stages.append(student_more_stage(cfg, launch, weighable))
    for stage in stages:
        check_inputs(stage_config(cfg, launch, stage))
    return [g for g in GROUPS if g in groups]


def check_resume_folder(cfg: DictConfig) -> None:
    """Refuse a pipeline's `train.resume` that is not a run folder of one."""
    folder = Path(cfg.train.resume)
    if not (folder / STAGES).is_file() and not any(folder.glob("teacher_*")):
        raise RealIkeaError(
            f"train.resume={folder}: a pipeline resumes from its run folder (holding "
            f"{STAGES} or teacher_* folders), not {'a file' if folder.is_file() else 'this'}"
        )


@dataclass
class Running:
    """A stage training in its own process: where its progress bar is and when it began."""

    process: multiprocessing.Process
    line: int
    begin: float
    resumed_at: int


def train_stage(config: dict, folder: str, label: str, line: int) -> None:
    """A stage's process: train the stage's config (a plain dict) in `folder`. Its first
    interrupt stops it (as in a launch of its own) and any later one is ignored, so that a
    Ctrl-C reaching it and the pipeline's own interrupt do not break its env pool's closing."""
    signal.signal(signal.SIGINT, interrupt_once)
    train(OmegaConf.create(config), Path(folder), label, line)


def interrupt_once(signum: int, frame) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    raise KeyboardInterrupt


def alone(cfg: DictConfig, stage: Stage) -> Stage:
    """The stage without `pipeline.side_by_side`, so with the launch's env workers."""
    beside = set(cfg.pipeline.side_by_side)
    return replace(stage, overrides=tuple(o for o in stage.overrides if o not in beside))


def longest_first(ready: list[Stage]) -> Stage:
    """The ready stage to start next: the longest; of equal ones a group's own teacher, then
    the first found."""
    return max(ready, key=lambda stage: (stage.iterations, bool(stage.category)))


class Pipeline:
    """The stages of one launch in its run folder `root`."""

    def __init__(self, cfg: DictConfig, launch: list[str], root: Path):
        self.cfg, self.launch, self.root = cfg, launch, Path(root)
        self.started = 0  # stages run or found done so far: the progress bar's stage number
        self.at_once = int(cfg.pipeline.stages_at_once)
        # with pipeline.best_teacher: each group's teacher so far, as (its success, own)
        self.best: dict[str, tuple[float, bool]] = {}
        # groups given a teacher of their own once their fine-tune missed (own_after_fine_tune)
        self.after_fine_tune: set[str] = set()

    def folder(self, stage: Stage) -> Path:
        return self.root if stage.name in (STUDENT, STUDENT_MORE) else self.root / stage.name

    def final(self, stage: Stage) -> Path:
        """The stage's last checkpoint once it is done."""
        return self.folder(stage) / f"model_{stage.iterations - 1}.pt"

    def prepare(self, stage: Stage, teachers: dict[str, Path] | None) -> tuple:
        """Ready the stage's folder: (its last checkpoint, or None) if done, else (None, its
        label, its config resuming its last checkpoint if it has one, that checkpoint's
        iteration or 0)."""
        self.started += 1
        label = f"stage {self.started} {stage.name}"
        folder = self.folder(stage)
        final = self.final(stage)
        if final.is_file():
            print(f"{label}: done ({final})", flush=True)
            return final, label, None, 0
        stage_cfg = stage_config(self.cfg, self.launch, stage, teachers)
        found = checkpoints(folder) if any(folder.glob("model_*.pt")) else []
        if found:
            last, path = found[-1]
            stage_cfg.train.resume = str(path)
            stage_cfg.agent.max_iterations = stage.iterations - last
        elif stage.starts_from:
            stage_cfg.train.init_actor = str(self.final(teacher_stage(self.cfg, stage.kind)))
        elif stage.name in (STUDENT, STUDENT_MORE):  # the run folder: never emptied
            (folder / "metrics.csv").unlink(missing_ok=True)  # a launch stopped before a checkpoint
        else:
            shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True, exist_ok=True)
        print(f"{label}: {' '.join(stage.overrides)}", flush=True)
        return None, label, stage_cfg, found[-1][0] if found else 0

    def run(self, stage: Stage, teachers: dict[str, Path] | None = None) -> Path:
        """Train the stage here (or continue it, or find it done); its last checkpoint."""
        done, label, stage_cfg, resumed_at = self.prepare(stage, teachers)
        if done:
            return done
        begin = time.time()
        checkpoint = train(stage_cfg, self.folder(stage), label)
        self.record(stage, begin, resumed_at, teachers)
        return checkpoint

    def start(self, stage: Stage, line: int) -> Path | Running:
        """Start the stage in its own process, its progress bar on `line`; or its last
        checkpoint if it is done."""
        done, label, stage_cfg, resumed_at = self.prepare(stage, None)
        if done:
            return done
        config = OmegaConf.to_container(stage_cfg)
        process = multiprocessing.get_context("spawn").Process(
            target=train_stage, args=(config, str(self.folder(stage)), label, line),
            name=stage.name,
        )  # fmt: skip
        process.start()
        return Running(process, line, time.time(), resumed_at)

    def finish(self, running: dict[Stage, Running]) -> tuple[Stage, Path]:
        """Wait for one of the running stages to end; it and its last checkpoint. A stage that
        fails stops the others and the pipeline, naming it."""
        ended = wait([job.process.sentinel for job in running.values()])
        stage, job = next((s, j) for s, j in running.items() if j.process.sentinel in ended)
        job.process.join()  # its sentinel closes as it exits, a moment before it can be reaped
        del running[stage]
        if job.process.exitcode != 0:
            stop(running)
            raise RealIkeaError(
                f"stage {stage.name} stopped with exit code {job.process.exitcode} (its error "
                f"is printed above; its folder: {self.folder(stage)})"
            )
        self.record(stage, job.begin, job.resumed_at)
        return stage, self.final(stage)

    def record(
        self, stage: Stage, begin: float, resumed_at: int, teachers: dict[str, Path] | None = None
    ) -> None:
        """Add the finished stage to RUN/stages.json (in place of an earlier record of it): its
        launch's wall seconds, start and end (Unix seconds), last-window success and (the
        student) each group's teacher stage."""
        end = time.time()
        stages = [s for s in self.records() if s["name"] != stage.name]
        success = last_window(self.folder(stage))
        taught_by = {g: checkpoint.parent.name for g, checkpoint in (teachers or {}).items()}
        stages.append({**asdict(stage), "resumed_at": resumed_at, "seconds": round(end - begin, 1),
                       "began": round(begin, 1), "ended": round(end, 1),
                       "success": {g: v for g, v in success.items() if v is not None},
                       **({"teachers": taught_by} if taught_by else {})})  # fmt: skip
        self.write_records(stages)

    def train(self, groups: list[str]) -> Path:
        """Every group's teacher, then the student (and, with `student_more`, the student read on
        its small-part reads and trained on, `student_on`); the student's last checkpoint."""
        teachers = self.teachers(groups)
        student = self.run(student_stage(self.cfg), teachers)
        if self.cfg.pipeline.student_more is None:
            return student
        return self.student_on(student, groups, teachers)

    def student_on(self, student: Path, groups: list[str], teachers: dict[str, Path]) -> Path:
        """Read the student on the small-part reads of its `judge_small_parts` groups (kept in
        its record, as a teacher's), then train it on from the same teachers with each group
        it reads below `student_more.below` weighted (`student_more_stage`)."""
        read = student_read_groups(self.cfg, groups)
        rates = self.judged(student_stage(self.cfg), student, read, "validation", small_only=True)
        below = float(self.cfg.pipeline.student_more.below)
        weak = [g for g in read if (rates[g] or 0.0) < below]
        print(f"student below {below} on the small parts: {', '.join(weak) or 'none'}", flush=True)
        return self.run(student_more_stage(self.cfg, self.launch, weak), teachers)

    def teachers(self, groups: list[str]) -> dict[str, Path]:
        """Train the kind teachers and the groups' own ones, `stages_at_once` at a time (here
        when one), each once the stage it needs is done; each group's teacher."""
        own = [g for g in own_teachers(self.cfg) if g in groups and not from_kind(self.cfg, g)]
        ready = kind_teacher_stages(self.cfg, groups)
        ready += [teacher_stage(self.cfg, *kind_and_category(group)) for group in own]
        teachers: dict[str, Path] = {}
        running: dict[Stage, Running] = {}
        try:
            while ready or running:
                while ready and len(running) < self.at_once:
                    stage = longest_first(ready)
                    ready.remove(stage)
                    if not ready and not running and self.cfg.pipeline.alone_all_workers:
                        stage = alone(self.cfg, stage)  # nothing can start before it ends
                    if self.at_once == 1:
                        ready += self.taught(stage, self.run(stage), groups, teachers)
                        continue
                    free = min(set(range(self.at_once)) - {j.line for j in running.values()})
                    started = self.start(stage, free)
                    if isinstance(started, Path):
                        ready += self.taught(stage, started, groups, teachers)
                    else:
                        running[stage] = started
                if running:
                    stage, checkpoint = self.finish(running)
                    ready += self.taught(stage, checkpoint, groups, teachers)
        except BaseException:
            stop(running)
            raise
        return teachers

    def taught(
        self, stage: Stage, checkpoint: Path, groups: list[str], teachers: dict[str, Path]
    ) -> list[Stage]:
        """Note the finished teacher in `teachers` for the groups it teaches (`offer`); the
        stages it makes ready: a kind's teacher-rule teachers, for its groups it left below
        `pipeline.learned` (as `pipeline.learned_judge` reads it), its fine-tunes, for those it
        left below `pipeline.fine_tune.below`, and its named group teachers that start from it
        (`from_kind`); or a named group teacher's retrain if it left its group under its retrain
        mark, or (`pipeline.learned_retrain_below`) a teacher-rule teacher's under that. A
        fine-tune teaches its group only if it ends higher on it than its kind's teacher. Success
        is as `pipeline.judge` says (`judged`)."""
        pipeline, judge = self.cfg.pipeline, str(self.cfg.pipeline.judge)
        if stage.category:
            group = group_name(stage.category, stage.kind)
            is_named = group in own_teachers(self.cfg)
            rule_mark = None if is_named else pipeline.learned_retrain_below
            # read only where a choice needs it: a fine-tune, a teacher that may retrain or be
            # retrained, or `best_teacher`; else a group's teacher teaches whatever it reads
            after = group in self.after_fine_tune  # its own teacher once its fine-tune missed
            read = (stage.name.endswith(FINE_TUNED) or is_named or rule_mark is not None
                    or pipeline.best_teacher or after) and group in groups  # fmt: skip
            success = self.judged(stage, checkpoint, [group] if read else [], judge)
            if stage.name.endswith(FINE_TUNED):
                self.offer(teachers, group, checkpoint, success, own=True, only_if_better=True)
                below = self.best[group][0] < float(pipeline.fine_tune.below)
                if not (pipeline.own_after_fine_tune and below):
                    return []
                self.after_fine_tune.add(group)
                return [teacher_stage(self.cfg, stage.kind, stage.category)]
            retrain = teacher_stage(self.cfg, stage.kind, stage.category, retrain=True)
            is_retrain = stage.name == retrain.name
            better = (is_retrain and pipeline.keep_better_retrain) or after
            self.offer(teachers, group, checkpoint, success, own=True, only_if_better=better)
            mark = retrain_mark(self.cfg, group) if is_named and pipeline.retrain_own else rule_mark
            if is_retrain or after or mark is None:
                return []
            return [retrain] if self.missed(success, group, mark) else []
        # its groups of the draw a rule reads it on: a named group's only to pick the better
        best, named = self.cfg.pipeline.best_teacher, own_teachers(self.cfg)
        ruled = [g for c in CATEGORIES if (g := group_name(c, stage.kind)) in groups
                 and (best or g not in named)]  # fmt: skip
        rule_judge = learned_judge(self.cfg)
        rule = self.judged(stage, checkpoint, ruled, rule_judge)
        # the groups it may teach or fine-tune: those it did not leave to a teacher of their own
        rated = [g for g in ruled if best or not self.missed(rule, g)]
        # one measure for both: `rule` already holds every group of `rated`
        success = rule if judge == rule_judge else self.judged(stage, checkpoint, rated, judge)
        later = []
        for category in CATEGORIES:
            group = group_name(category, stage.kind)
            if group not in groups:
                continue
            missed = group not in named and self.missed(rule, group)
            if missed or from_kind(self.cfg, group):
                later.append(teacher_stage(self.cfg, stage.kind, category))
            elif fine_tuned(self.cfg, group, success[group] or 0.0):
                later.append(fine_tune_stage(self.cfg, stage.kind, category))
            # a group with a teacher of its own keeps its kind's only as the better one
            if group in rated:
                self.offer(teachers, group, checkpoint, success, own=False)
        return later

    def judged(
        self,
        stage: Stage,
        checkpoint: Path,
        groups: list[str],
        judge: str,
        small_only: bool = False,
    ) -> dict[str, float | None]:
        """Each group's success of the finished teacher (`judge`): its training success over its
        last full window, or with `validation` that of its mean action on the validation draw,
        judged on `groups`, the lowest over the launch's resistance mode, each of
        `pipeline.judge_resistances` and, for the groups of `pipeline.judge_small_parts`, their
        small-part reads (`validation_success`; kept in RUN/stages.json under the stage's
        record, `validation`, `validation_<mode>` and `validation_<small-part read>`, so a
        resumed launch does not judge it again); with `small_only`, those reads alone (a group
        without one: None)."""
        if judge == "training":
            return last_window(checkpoint.parent)
        stages = self.records()
        record = next((s for s in stages if s["name"] == stage.name), {})
        small_reads = {g: judged_small_part_reads(self.cfg, g) for g in GROUPS}
        # each read: its key in the record, the groups it applies to, how it is read
        plan = [(f"validation_{m}" if m else "validation", set(GROUPS), (m,), {})
                for m in ([] if small_only else judged_modes(self.cfg))]  # fmt: skip
        plan += [
            (f"validation_{read}", {g for g in GROUPS if read in small_reads[g]}, (),
             {"small_parts": read})
            for read in SMALL_PART_SIDES
        ]  # fmt: skip
        reads = []
        for key, applies, mode, small_parts in plan:
            judged = record.get(key, {})
            missing = [g for g in groups if g in applies and g not in judged]
            if missing:
                episodes = int(self.cfg.pipeline.validation_episodes)
                judged |= validation_success(
                    checkpoint, missing, episodes, self.launch, stage.name, *mode, **small_parts
                )
                if record:
                    record[key] = judged
                    self.write_records(stages)
            reads.append((applies, judged))
        rates = {g: [judged.get(g) for applies, judged in reads if g in applies] for g in GROUPS}
        return {g: None if None in r or not r else min(r) for g, r in rates.items()}

    def records(self) -> list[dict]:
        """The finished stages' records in RUN/stages.json (none yet: empty)."""
        path = self.root / STAGES
        return json.loads(path.read_text()) if path.is_file() else []

    def write_records(self, stages: list[dict]) -> None:
        """Replace RUN/stages.json with `stages`, atomically."""
        atomic_write_text(self.root / STAGES, json.dumps(stages, indent=1) + "\n")

    def offer(
        self,
        teachers: dict[str, Path],
        group: str,
        checkpoint: Path,
        success: dict[str, float | None],
        own: bool,
        only_if_better: bool = False,
    ) -> None:
        """Make `checkpoint` the group's teacher: always (a group's own teacher, or its
        retrain, replaces what it had), or with `pipeline.best_teacher` (or `only_if_better`)
        only if its success on the group is above the group's teacher so far (equal:
        a group's own teacher goes before its kind's, the first own one before its retrain)."""
        score = (success[group] or 0.0, own)
        choose = self.cfg.pipeline.best_teacher or only_if_better
        if not choose or score > self.best.get(group, (-1.0, False)):
            teachers[group], self.best[group] = checkpoint, score

    def missed(
        self, success: dict[str, float | None], group: str, mark: float | None = None
    ) -> bool:
        """Whether a teacher left the group below `mark`, by default `pipeline.learned` (no
        full window: 0)."""
        return (success[group] or 0.0) < float(self.cfg.pipeline.learned if mark is None else mark)


def stop(running: dict[Stage, Running]) -> None:
    """Stop the stages' processes by an interrupt (each closes its env pool and exits)."""
    for job in running.values():
        if job.process.is_alive():
            os.kill(job.process.pid, signal.SIGINT)
    for job in running.values():
        job.process.join()
    running.clear()


def check_launch(cfg: DictConfig, launch: list[str]) -> list[str]:
    """Every check of a pipeline launch that needs no simulation (no length of its own, its
    resume folder, its settings, every stage known before training: `check_stages`); the
    draw's groups."""
    name = cfg.pipeline.name
    refused = {key: f"each stage of pipeline={name} sets its own; set {instead}"
               for key, instead in STAGE_SET.items()}  # fmt: skip
    # not a STAGE_SET key: the student's own overrides may set it
    refused["asset.group_weights"] = (
        f"every stage of pipeline={name} would take it, and a group's own teacher "
        "(asset=<category>) draws one group; weigh the student's draw in pipeline.student.overrides"
    )
    for key, why in refused.items():
        if overrides_set(launch, key):
            raise RealIkeaError(f"{key}: {why}")
    if cfg.train.resume:
        check_resume_folder(cfg)
    return check_stages(cfg, launch)


def train_pipeline(cfg: DictConfig, run_dir: Path, launch: list[str]) -> Path:
    """Train the launch's pipeline in `run_dir` (or continue it in `train.resume`'s folder),
    every stage checked first; returns the student's last checkpoint."""
    groups = check_launch(cfg, launch)
    return Pipeline(cfg, launch, Path(cfg.train.resume or run_dir)).train(groups)
