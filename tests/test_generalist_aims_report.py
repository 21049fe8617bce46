"""The aims' report (experiments/generalist/aims_report.py): each seed's groups against the marks,
the verdicts, wall time, and the hull finger-pull door left out only once its check failed."""

from __future__ import annotations

import json

import pytest


@pytest.fixture
def report(load_script, monkeypatch, tmp_path):
    module = load_script("experiments/generalist/aims_report.py")
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    monkeypatch.setattr(module, "HULL_FP_DOOR", tmp_path / "hull_fp_door")
    return module


def test_a_group_below_its_mark_misses_the_aim_and_is_named(report, tmp_path, write_cells):
    write_cells(tmp_path / "default/s200", ("smooth", "high"), low=("door", "knob", "high", 0.68))
    (tmp_path / "default/s200/wall.json").write_text('{"launches_seconds": [3600, 2400]}')
    write_cells(tmp_path / "default/s201", ("smooth", "high"))
    report.main([])
    figures = json.loads((tmp_path / "aims.json").read_text())
    assert figures["default/s200"]["aim_coacd"] == {
        "met": False, "below": ["door knob high 0.68"], "excluded": []
    }  # fmt: skip
    assert figures["default/s200"]["wall_hours"] == pytest.approx(6000 / 3600)
    assert figures["default/s200"]["within_time"] is True
    assert figures["default/s201"]["aim_coacd"]["met"] is True
    assert figures["default/s202"]["aim_coacd"]["met"] is None  # nothing evaluated yet
    rate = figures["default/s200"]["rates"]["coacd"]["knob_door"]["high"]  # for README quotes
    assert rate == pytest.approx([0.68, 0.5418, 0.7924], abs=1e-4)
    assert figures["default/s202"]["rates"] == {"coacd": {}}
    text = (tmp_path / "aims.md").read_text()
    assert "0.68 [0.54, 0.79] ✗" in text and "- aim (coacd): missed; below: door knob high" in text


def test_the_hull_finger_pull_door_leaves_the_own_hull_aim_only_once_its_check_fails(
    report, tmp_path, write_cells
):
    low = ("door", "finger_pull", "high", 0.0)
    write_cells(tmp_path / "hull_high/s210_own", ("high",), low=low)
    write_cells(tmp_path / "hull_high/s210", ("high",), low=low)
    report.main([])
    own = json.loads((tmp_path / "aims.json").read_text())["hull_high/s210"]["aim_own"]
    assert own["met"] is False  # the check has not run: the group counts
    check = tmp_path / "hull_fp_door" / report.HULL_FP_DOOR_RUN.name
    write_cells(check, ("high",), success=0.2)
    report.main([])
    figures = json.loads((tmp_path / "aims.json").read_text())["hull_high/s210"]
    assert figures["aim_own"] == {"met": True, "below": [], "excluded": ["door finger_pull"]}
    assert "aim_coacd" not in figures  # the design card's policy on CoACD: reported, no aim
    assert set(figures["rates"]) == {"own", "coacd"}
    write_cells(check, ("high",), success=0.3)  # the check opens it: it counts again
    report.main([])
    figures = json.loads((tmp_path / "aims.json").read_text())["hull_high/s210"]
    assert figures["aim_own"]["met"] is False


def test_a_superseded_recipes_runs_report_on_their_own_under_their_own_name(
    report, tmp_path, write_cells
):
    write_cells(tmp_path / "default_group_ppo/s200", ("smooth", "high"))
    (tmp_path / "hull_high_group_ppo/s210").mkdir(parents=True)
    report.main(["--superseded", "group_ppo"])
    figures = json.loads((tmp_path / "aims_group_ppo.json").read_text())
    assert figures["default_group_ppo/s200"]["aim_coacd"]["met"] is True
    assert "hull_high_group_ppo/s210" in figures and not (tmp_path / "aims.json").exists()
    text = (tmp_path / "aims_group_ppo.md").read_text()
    assert "`group_ppo`, superseded" in text and "default_group_ppo/s200/learning_curve" in text
    # a seed the superseded recipe never ran (round 18's: none of the design card's) is named
    assert "### `default` seed 201: not run on `group_ppo`" in text
    assert "hull_high_group_ppo/s211" not in figures
    with pytest.raises(SystemExit):  # no such recipe's folders: refused, nothing written
        report.main(["--superseded", "bogus"])
    assert not (tmp_path / "aims_bogus.json").exists()


def test_a_run_whose_stages_trained_longer_than_its_launches_has_no_one_wall_time(
    report, tmp_path, write_cells
):
    """Stages copied from earlier runs (the union of their stages.json intervals beyond the
    launches' wall.json) leave the time aim unjudged, with the stages' minutes as a floor."""
    run = tmp_path / "default/s200"
    write_cells(run, ("smooth", "high"))
    (run / "wall.json").write_text('{"launches_seconds": [1500]}')
    stages = [{"name": "teacher_door", "began": 0.0, "ended": 3000.0},
              {"name": "teacher_drawer", "began": 1000.0, "ended": 4000.0},  # overlaps
              {"name": "student", "began": 9000.0, "ended": 10000.0},
              {"name": "teacher_flap"}]  # fmt: skip
    (run / "stages.json").write_text(json.dumps(stages))
    report.main([])
    figures = json.loads((tmp_path / "aims.json").read_text())["default/s200"]
    assert figures["stage_hours"] == pytest.approx(5000 / 3600)
    assert figures["within_time"] is None
    text = (tmp_path / "aims.md").read_text()
    assert "Wall time: 25.0 min (`wall.json`); its stages trained over 83.3 min" in text
    (run / "wall.json").write_text('{"launches_seconds": [6000]}')  # one run trained them all
    report.main([])
    assert json.loads((tmp_path / "aims.json").read_text())["default/s200"]["within_time"] is True
