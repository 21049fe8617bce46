"""The generalist screen's driver (experiments/generalist/screen.py): which runs a distilled
pipeline trains after its teachers, and the wall-time budget its stages share (no training)."""

from __future__ import annotations

import json

import pytest

from realikea.assets.catalog import GROUPS


@pytest.fixture
def screen(load_script):
    return load_script("experiments/generalist/screen.py")


def keep_by_hand(kept, name, successes: dict[str, float], seconds: float, iterations=400):
    """A kept run: `successes` per group logged over its last iterations, one launch."""
    folder = kept / name
    folder.mkdir(parents=True)
    rows = ["iteration,tag,value"]
    for it in range(iterations - 30, iterations):
        rows += [f"{it},/success/{group},{value}" for group, value in successes.items()]
    (folder / "metrics.csv").write_text("\n".join(rows) + "\n")
    (folder / f"model_{iterations - 1}.pt").write_bytes(b"")
    (folder / "wall.json").write_text(json.dumps({"launches_seconds": [seconds]}))


def log_pad_enters(folder, value: float, iterations=200):
    """Add to a kept run's last 30 iterations its finger pulls' success on channels the pad
    enters, the rows in one launch's order."""
    metrics = folder / "metrics.csv"
    header, *rows = metrics.read_text().splitlines()
    rows += [f"{it},/pad_enters_success/finger_pull_{kind},{value}"
             for it in range(iterations - 30, iterations)
             for kind in ("drawer", "door", "flap")]  # fmt: skip
    rows.sort(key=lambda row: int(row.split(",")[0]))
    metrics.write_text("\n".join([header, *rows]) + "\n")


class Recorder:
    """Stands in for the queue's training: records what each stage would run."""

    def __init__(self):
        self.runs = []

    def __call__(self, runs, dry_run, park):
        self.runs += runs
        return 0


def test_a_group_its_kinds_teacher_missed_gets_its_own_teacher_on_the_next_seed(screen, tmp_path):
    driver = screen.Screen(tmp_path / "work", tmp_path / "kept", None)
    kinds = {"drawer": 0.9, "door": 0.9, "flap": 0.9}
    for kind, value in kinds.items():
        groups = {f"{c}_{kind}": value for c in ("knob", "two_point", "finger_pull")}
        if kind == "door":
            groups["finger_pull_door"] = 0.3
        keep_by_hand(tmp_path / "kept", f"distilled_s20/teacher_{kind}", groups, 600.0)
    driver.run = Recorder()
    driver.distilled("distilled", 20, 0.5, False, dry_run=False, park=False)
    retrain = driver.run.runs[-1]  # and nothing after it until it is kept
    assert retrain.name == "distilled_s20/teacher_finger_pull_door"
    assert {"env.seed=21", "asset=finger_pull", "asset.kind=door"} <= set(retrain.overrides)
    keep_by_hand(tmp_path / "kept", retrain.name, {"finger_pull_door": 0.7}, 300.0)
    driver.distilled("distilled", 20, 0.5, False, dry_run=False, park=False)
    student = driver.run.runs[-1]
    assert student.name == "distilled_s20/student"
    teachers = next(o for o in student.overrides if o.startswith("distill.teachers="))
    assert f"finger_pull_door: {tmp_path}/kept/{retrain.name}/model_399.pt" in teachers
    assert driver.spent("distilled_s20") == 2100.0


def test_the_student_is_routed_to_each_groups_teacher(screen, tmp_path):
    driver = screen.Screen(tmp_path / "work", tmp_path / "kept", None)
    for kind in ("drawer", "door", "flap"):
        groups = {f"{c}_{kind}": 0.8 for c in ("knob", "two_point", "finger_pull")}
        keep_by_hand(tmp_path / "kept", f"distilled_s20/teacher_{kind}", groups, 600.0)
    driver.run = Recorder()
    driver.distilled("distilled", 20, 0.5, False, dry_run=False, park=False)
    (student,) = [r for r in driver.run.runs if r.name.endswith("student")]
    teachers = next(o for o in student.overrides if o.startswith("distill.teachers="))
    door = tmp_path / "kept/distilled_s20/teacher_door/model_399.pt"
    assert f"knob_door: {door}" in teachers and teachers.count("teacher_flap") == 3


def test_a_pipeline_whose_budget_is_spent_trains_nothing_more(screen, tmp_path, capsys):
    driver = screen.Screen(tmp_path / "work", tmp_path / "kept", None)
    keep_by_hand(tmp_path / "kept", "distilled_s20/teacher_drawer", {}, screen.BUDGET_SECONDS)
    driver.run = Recorder()
    driver.distilled("distilled", 20, 0.5, False, dry_run=False, park=False)
    assert driver.run.runs == []
    assert "distilled_s20: its 2 h are spent" in capsys.readouterr().out


def test_a_single_run_candidate_that_misses_its_rounds_mark_stops_at_that_seed(screen, tmp_path):
    kept = tmp_path / "kept"
    groups = {g: 0.9 for g in GROUPS} | {"finger_pull_door": 0.7}
    keep_by_hand(kept, "fp_pregrasp_s20", groups, 6000.0, iterations=1500)
    driver = screen.Screen(tmp_path / "work", kept, None)
    driver.run = Recorder()
    assert driver.single("fp_pregrasp", 20, 0.5, dry_run=False, park=False)
    assert not driver.single("fp_pregrasp", 20, screen.MARKS[2], dry_run=False, park=False)
    assert {"+task.pregrasp_groups=[finger_pull_door]", "env.seed=20"} <= set(
        screen.single_run("fp_pregrasp", 20).overrides
    )
    assert "agent=ppo" not in screen.single_run("fp_pregrasp", 20).overrides


def test_a_candidate_of_another_round_is_refused(screen, capsys):
    with pytest.raises(SystemExit):
        screen.main(["--round", "2", "--candidates", "group_ppo", "--dry-run"])
    assert "group_ppo not in round 2" in capsys.readouterr().err


def test_round_three_runs_the_default_with_the_opening_paid_past_the_mark(screen):
    assert screen.ROUNDS[3] == ("open_margin",)
    assert screen.MARKS[3] == 0.8
    overrides = screen.single_run("open_margin", 21).overrides
    assert {"task.reward.open_target=1.25", "env.seed=21", "agent.max_iterations=1500"} <= set(
        overrides
    )
    assert "agent=ppo" not in overrides


def test_round_four_runs_the_default_with_open_jaws_paid_only_before_a_grasp(screen):
    assert screen.ROUNDS[4] == ("hold_grasp",)
    assert screen.MARKS[4] == 0.8
    overrides = screen.single_run("hold_grasp", 20).overrides
    assert {"task.reward.reopen_bonus=false", "env.seed=20", "agent.max_iterations=1500"} <= set(
        overrides
    )
    assert "agent=ppo" not in overrides


def test_round_five_runs_the_default_with_each_envs_configuration_rotating(screen):
    assert screen.ROUNDS[5] == ("rotate",)
    assert screen.MARKS[5] == 0.8
    overrides = screen.single_run("rotate", 21).overrides
    assert {"asset.rotate_every=10", "env.seed=21", "agent.max_iterations=1500"} <= set(overrides)
    assert "agent=ppo" not in overrides


def test_round_six_rotates_and_starts_some_finger_pull_doors_ajar(screen):
    assert screen.ROUNDS[6] == ("rotate_ajar",)
    assert screen.MARKS[6] == 0.8
    overrides = screen.single_run("rotate_ajar", 20).overrides
    assert {
        "asset.rotate_every=10",
        "+task.ajar_share=0.3",
        "+task.ajar_groups=[finger_pull_door]",
        "+task.ajar_range=[0.4,1.0]",
        "env.seed=20",
        "agent.max_iterations=1500",
    } <= set(overrides)
    assert "agent=ppo" not in overrides


def test_round_seven_distils_rotating_teachers_and_a_finger_pull_door_specialist(screen, tmp_path):
    assert screen.ROUNDS[7] == ("distilled_rotate",)
    assert screen.MARKS[7] == 0.8 and 7 in screen.PAD_ENTERS_ROUNDS
    kept = tmp_path / "kept"
    driver = screen.Screen(tmp_path / "work", kept, None)
    for kind in ("drawer", "door", "flap"):
        groups = {f"{c}_{kind}": 0.9 for c in ("knob", "two_point", "finger_pull")}
        keep_by_hand(kept, f"distilled_rotate_s20/teacher_{kind}", groups, 900.0)
    assert {"asset.rotate_every=10", "asset.kind=door", "env.seed=20", "agent=ppo"} <= set(
        screen.teacher_run("distilled_rotate", 20, "door").overrides
    )
    driver.run = Recorder()
    assert driver.distilled("distilled_rotate", 20, 0.8, True, dry_run=False, park=False)
    # finger-pull doors get their specialist although the door teacher learned them
    specialist = driver.run.runs[-1]
    assert specialist.name == "distilled_rotate_s20/teacher_finger_pull_door"
    recipe = {"asset=finger_pull", "asset.kind=door", "asset.rotate_every=10", "env.seed=20",
              "agent.max_iterations=1000", "dr.switch_iteration=500"}  # fmt: skip
    assert recipe <= set(specialist.overrides)
    keep_by_hand(kept, specialist.name, {"finger_pull_door": 0.77}, 1800.0, iterations=1000)
    driver.distilled("distilled_rotate", 20, 0.8, True, dry_run=False, park=False)
    student = driver.run.runs[-1]
    assert student.name == "distilled_rotate_s20/student"
    assert "asset.rotate_every=10" in student.overrides
    teachers = next(o for o in student.overrides if o.startswith("distill.teachers="))
    assert f"finger_pull_door: {kept}/{specialist.name}/model_999.pt" in teachers
    assert f"knob_door: {kept}/distilled_rotate_s20/teacher_door/model_399.pt" in teachers
    # the student is read on channels the pad enters: 0.9 there passes, the 0.7 over all fails
    groups = {g: 0.9 for g in GROUPS} | {"finger_pull_door": 0.7}
    keep_by_hand(kept, student.name, groups, 600.0, iterations=200)
    assert not driver.distilled("distilled_rotate", 20, 0.8, True, dry_run=False, park=False)
    log_pad_enters(kept / student.name, 0.9)
    assert driver.distilled("distilled_rotate", 20, 0.8, True, dry_run=False, park=False)
    assert driver.spent("distilled_rotate_s20") == 5100.0


def test_round_eight_is_one_staged_launch_judged_on_its_student(screen, tmp_path):
    """distilled_pairs: round 7's stages in one launch of the pipeline (the teachers two at a
    time), kept with its stages; its student read on channels the pad enters."""
    assert screen.ROUNDS[8] == ("distilled_pairs",)
    assert screen.MARKS[8] == 0.8 and 8 in screen.PAD_ENTERS_ROUNDS
    run = screen.staged_run("distilled_pairs", 21)
    assert run.staged and run.iterations == 200 and run.name == "distilled_pairs_s21"
    assert set(run.overrides) == {"logger=none", "pipeline=distilled_pairs", "env.seed=21"}
    kept = tmp_path / "kept"
    groups = {g: 0.9 for g in GROUPS} | {"finger_pull_door": 0.7}
    keep_by_hand(kept, run.name, groups, 4000.0, iterations=200)
    driver = screen.Screen(tmp_path / "work", kept, None)
    driver.run = Recorder()
    assert not driver.single("distilled_pairs", 21, 0.8, False, False, reading=True)
    log_pad_enters(kept / run.name, 0.9)
    assert driver.single("distilled_pairs", 21, 0.8, False, False, reading=True)
    assert not driver.single("distilled_pairs", 21, 0.8, dry_run=False, park=False)  # over all
    assert driver.run.runs == [run] * 3


@pytest.mark.parametrize(
    "round_, candidate, student",
    [
        (9, "distilled_pairs_knob", 200),
        (10, "distilled_pairs_retry", 200),
        (11, "distilled_pairs_long_knob", 200),
        (12, "distilled_pairs_knob_fixed_lr", 200),
        (13, "distilled_pairs_long_student", 400),
        (14, "distilled_pairs_best_teacher", 400),
        (15, "distilled_pairs_knob_from_door", 400),
        (16, "distilled_pairs_student_doors2", 400),
        (17, "distilled_pairs_knob_second_teacher", 400),
        (18, "distilled_pairs_student_96", 400),
        (19, "distilled_pairs_fine_tune", 400),
        (20, "distilled_pairs_validated", 400),
        (21, "distilled_pairs_validated_marks", 400),
        (22, "distilled_pairs_rule_retrain", 400),
        (23, "distilled_pairs_student_mean", 400),
        (24, "distilled_pairs_student_noise", 400),
        (25, "distilled_pairs_judged_high", 400),
        (26, "distilled_pairs_small_parts", 400),
        (27, "distilled_pairs_student_small_parts", 600),  # the student's 400 and 200 more
        (28, "distilled_pairs_student_mirrored", 600),
    ],
)
def test_rounds_nine_on_are_staged_launches_of_their_pipelines(screen, round_, candidate, student):
    assert screen.ROUNDS[round_] == (candidate,)
    assert screen.MARKS[round_] == 0.8 and round_ in screen.PAD_ENTERS_ROUNDS
    run = screen.staged_run(candidate, 20)
    assert run.staged and run.iterations == student
    assert set(run.overrides) == {"logger=none", f"pipeline={candidate}", "env.seed=20"}
