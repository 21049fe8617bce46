"""Where a cell's misses go wrong (experiments/generalist/misses.py): the sorting by hand, and one
committed-looking cell rerun and recorded end to end."""

from __future__ import annotations

import json

import numpy as np
import pytest

from realikea.errors import RealIkeaError

PIN = "asset=two_point asset.part=tp_round_bar_128 asset.base=drawer_w60_h20"
# two 10 s episodes of the heuristic pull on one configuration: it pinches the bar open
COMMAND = (
    f"realikea eval policy=heuristic_pull {PIN} asset.split=train dr=fixed episodes=2 "
    "env.num_workers=0 task.episode_seconds=10"
)


@pytest.fixture
def misses(load_script):
    return load_script("experiments/generalist/misses.py")


def episode(
    outcome: str,
    peak: float,
    base: str = "door_left_w40_h80",
    end: str = "timeout",
    part: str = "fp_lip_36",
    mode: str | None = "other",
):
    row = {"outcome": outcome, "peak_opening": peak, "base": base, "termination": end}
    row["hinge"] = base.split("_")[1] if base.startswith("door_") else ""
    return row | {
        "part": part,
        "failure_mode": None if outcome == "success" else mode,
        "let_go": outcome == "partial",
    }


def cell(command: str = "realikea eval ...", **rates) -> dict:
    graded = {"fail": 0.0, "partial": 0.0, "success": 0.0} | rates
    where = {"kind": "door", "category": "finger_pull", "resistance": "smooth", "episodes": 4}
    return where | graded | {"command": command}


def test_a_miss_that_once_stood_past_the_mark_is_counted_as_let_fall_back(misses):
    rows = [
        episode("success", 0.95, end="stagnation"),
        episode("partial", 0.82),  # opened past 0.785, ended below it
        episode("partial", 0.60, base="door_right_w60_h80", part="fp_cup_96"),  # never reached it
        episode("fail", 0.0, "door_right_w60_h80", "stagnation", "fp_cup_96", "narrow_clearance"),
    ]
    graded = cell(partial=0.5, fail=0.25, success=0.25)
    text = misses.report(rows, graded, 0.785, "rad", graded["command"])
    assert "3 of 4 episodes missed; **1 of them had reached the mark" in text
    assert "(peak openings 0.82 rad)" in text
    assert "median 0.95, least 0.95 rad" in text
    assert "| partial | yes | timeout | 1 |" in text
    assert "| partial | no | timeout | 1 |" in text
    assert "| fail | no | stagnation | 1 |" in text
    assert "| door_right_w60_h80 | 1 | 1 | 0 |" in text
    assert "| door_left_w40_h80 | 0 | 1 | 1 |" in text
    assert "| left | 0 | 1 | 1 |" in text and "| right | 1 | 1 | 0 |" in text  # hinge sides
    assert "| fp_lip_36 | 1 / 2 | – |" in text and "| fp_cup_96 | – | 0 / 2 |" in text
    assert "| other | 2 |" in text and "| narrow_clearance | 1 |" in text  # the misses' modes
    assert "| fp_cup_96 | 1 | 1 | 0 |" in text
    assert "| fp_lip_36 | 0 | 1 | 1 |" in text
    assert "| partial | 2 | 2 |" in text and "| success | 1 | 0 |" in text  # let go of a grasp


def test_a_grasp_is_let_go_when_the_jaws_open_after_it_first_engaged(misses):
    engaged = np.array([False, True, True, False, False])
    assert misses.let_go(engaged, np.array([1.0, 0.1, 0.1, 0.9, 0.9]))
    assert not misses.let_go(engaged, np.array([1.0, 0.1, 0.1, 0.3, 0.1]))  # still closed
    assert not misses.let_go(np.zeros(5, bool), np.ones(5))  # open, never engaged


def test_the_validation_draw_replaces_the_cells_parts_and_seed(misses):
    test_draw = "realikea eval policy.path=a/model_9.pt asset.split=test episodes=50 env.seed=1000"
    assert misses.on_validation_draw(test_draw) == (
        "realikea eval policy.path=a/model_9.pt episodes=50 asset.split=train env.seed=2000"
    )


def test_another_checkpoint_replaces_the_cells_policy_path(misses):
    command = "realikea eval policy=checkpoint policy.path=a/model_9.pt episodes=50"
    assert misses.with_checkpoint(command, "b/teacher_door/model_399.pt") == (
        "realikea eval policy=checkpoint episodes=50 policy.path=b/teacher_door/model_399.pt"
    )


@pytest.mark.parametrize(
    ("extra", "refusal"),
    [
        (["--checkpoint", "teacher_door/model_399.pt"], "validation draw only: add --validation"),
        (["--validation", "--checkpoint", "absent/model_1.pt"], "absent/model_1.pt: no such file"),
    ],
)
def test_a_checkpoint_off_the_validation_draw_or_missing_is_refused_before_any_rerun(
    misses, tmp_path, monkeypatch, capsys, extra, refusal
):
    run = tmp_path / "s1"
    run.mkdir()
    (run / "cells.jsonl").write_text(json.dumps(cell(success=1.0)) + "\n")
    (tmp_path / "teacher_door").mkdir()
    (tmp_path / "teacher_door/model_399.pt").touch()
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(misses, "record", lambda *a: pytest.fail("a rerun started"))
    args = [str(run), "--category", "finger_pull", "--kind", "door", "--resistance", "smooth"]
    with pytest.raises(SystemExit) as exit_:
        misses.main(args + extra)
    assert exit_.value.code == 2
    assert refusal in capsys.readouterr().err
    assert not (run / "misses").exists()


def test_a_rerun_graded_otherwise_than_the_committed_cell_is_refused(misses):
    rows = [episode("success", 0.9)] * 3 + [episode("partial", 0.5)]
    misses.check_rates(rows, cell(success=0.75, partial=0.25))
    with pytest.raises(RealIkeaError, match="not the same episodes"):
        misses.check_rates(rows, cell(success=1.0))


def test_a_cell_the_run_never_evaluated_is_refused_before_any_rerun(
    misses, tmp_path, monkeypatch, capsys
):
    run = tmp_path / "s1"
    run.mkdir()
    (run / "cells.jsonl").write_text(json.dumps(cell(success=1.0)) + "\n")
    monkeypatch.setattr(misses, "record", lambda *a: pytest.fail("a rerun started"))
    with pytest.raises(SystemExit) as exit_:
        misses.main([str(run), "--category", "knob", "--kind", "door", "--resistance", "smooth"])
    assert exit_.value.code == 2
    assert "no knob door cell in smooth" in capsys.readouterr().err
    assert not (run / "misses").exists()


def test_a_committed_cell_is_rerun_recorded_and_sorted(misses, tmp_path):
    run = tmp_path / "s1"
    run.mkdir()
    library = tmp_path / "library"
    record = cell(f"{COMMAND} paths.library={library}", success=1.0) | {
        "kind": "drawer", "category": "two_point", "episodes": 2,
    }  # fmt: skip
    (run / "cells.jsonl").write_text(json.dumps(record) + "\n")
    args = [str(run), "--category", "two_point", "--kind", "drawer", "--resistance", "smooth"]
    assert misses.main(args) == 0
    text = (run / "misses/two_point_drawer_smooth.md").read_text()
    assert "Success mark 0.2 m" in text
    assert "0 of 2 episodes missed; **0 of them had reached the mark" in text
    assert "| drawer_w60_h20 | 0 | 0 | 2 |" in text
    assert "| tp_round_bar_128 | 0 | 0 | 2 |" in text
    assert "hinge side" not in text  # a drawer has none
    kept = [json.loads(line) for line in (run / "misses/two_point_drawer_smooth.jsonl").open()]
    assert [(e["part"], e["base"], e["outcome"]) for e in kept] == [
        ("tp_round_bar_128", "drawer_w60_h20", "success")
    ] * 2
    assert set(kept[0]) == set(misses.EPISODE_KEYS)
    assert "| success | 2 | " in text  # each success sorted by whether it let go
    assert "(same grades as the committed cell)" in text


def test_a_run_with_no_cells_is_read_on_the_validation_draw_only(
    misses, tmp_path, monkeypatch, capsys
):
    run = tmp_path / "hold_grasp_s20"
    run.mkdir()
    (run / "model_1499.pt").touch()
    monkeypatch.setattr(misses, "record", lambda *a: pytest.fail("a rerun started"))
    with pytest.raises(SystemExit) as exit_:
        misses.main([str(run), "--category", "knob", "--kind", "door", "--resistance", "smooth"])
    assert exit_.value.code == 2
    assert "validation draw only (--validation)" in capsys.readouterr().err
    assert not (run / "misses").exists()


def test_a_screen_runs_cell_is_its_last_checkpoint_on_an_aim_runs_evaluation(misses, tmp_path):
    run = tmp_path / "hold_grasp_s20"
    run.mkdir()
    for it in (50, 1499, 400):
        (run / f"model_{it}.pt").touch()
    cell = misses.screen_cell(run, "door", "finger_pull", "high")
    assert (cell["kind"], cell["category"], cell["resistance"]) == ("door", "finger_pull", "high")
    words = cell["command"].split()
    assert words[:3] == ["realikea", "eval", "policy=checkpoint"]
    assert words[3].endswith("hold_grasp_s20/model_1499.pt")
    assert "asset=finger_pull" in words and "resistance=high" in words
    validation = misses.on_validation_draw(cell["command"]).split()
    assert validation[-2:] == ["asset.split=train", "env.seed=2000"]
    assert "asset.split=test" not in validation and "env.seed=1000" not in validation
