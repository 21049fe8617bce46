"""The generalist screen's adoption rule (experiments/generalist/screen_rule.py), by hand."""

from __future__ import annotations

import pytest


@pytest.fixture
def rule(load_script):
    return load_script("experiments/generalist/screen_rule.py")


def write_run(folder, groups, iterations: int, success, skip=()):
    """A run logging each of `groups`' success every iteration (`success(group, it)`), but not
    the groups in `skip`, and a seconds-stepped `/time` tag far past its iterations."""
    folder.mkdir()
    rows = ["iteration,tag,value"]
    for it in range(iterations):
        rows += [f"{it},Train/mean_reward,1.0", f"{it * 9},Train/mean_reward/time,1.0"]
        rows += [f"{it},/success/{g},{success(g, it)}" for g in groups if g not in skip]
    (folder / "metrics.csv").write_text("\n".join(rows) + "\n")
    return folder


def test_every_group_over_the_last_25_iterations_decides(rule, tmp_path, capsys):
    groups = rule.GROUPS
    good = write_run(tmp_path / "good", groups, 100, lambda g, it: float(it >= 75))
    # the last group learned, then lost in the last 25 iterations (0.48 there)
    lost = write_run(
        tmp_path / "lost", groups, 100, lambda g, it: float(g != groups[-1] or it % 25 >= 13)
    )
    assert rule.last_window(good)[groups[0]] == 1.0
    assert rule.last_window(lost)[groups[-1]] == pytest.approx(12 / 25)
    assert rule.main([str(good)]) == 0
    assert rule.main([str(good), str(lost)]) == 1
    assert "adopted: no (1 of 2 runs pass at 0.5)" in capsys.readouterr().out


def test_round_twos_mark_is_stricter(rule, tmp_path, capsys):
    groups = rule.GROUPS
    # every group at 0.76 over the last 25 iterations: learned by round 1's mark, not round 2's
    run = write_run(tmp_path / "run", groups, 50, lambda g, it: float(it % 25 < 19))
    assert rule.main([str(run)]) == 0
    assert rule.main(["--mark", "0.8", str(run)]) == 1
    assert "adopted: no (0 of 1 runs pass at 0.8)" in capsys.readouterr().out
    assert rule.main(["--mark", "80", str(run)]) == 2


def test_a_missing_group_or_a_run_shorter_than_the_window_fails(rule, tmp_path):
    groups = rule.GROUPS
    absent = write_run(tmp_path / "absent", groups, 100, lambda g, it: 1.0, skip=(groups[3],))
    short = write_run(tmp_path / "short", groups, 24, lambda g, it: 1.0)
    assert rule.last_window(absent)[groups[3]] is None and rule.main([str(absent)]) == 1
    assert set(rule.last_window(short).values()) == {None} and rule.main([str(short)]) == 1
    assert rule.main([str(tmp_path / "nothing")]) == 2


def test_round_seven_reads_finger_pulls_on_channels_the_pad_enters(rule, tmp_path, capsys):
    groups = rule.GROUPS
    # every group at 0.9, finger-pull doors at 0.76 over all parts and 0.88 on those the pad enters
    run = write_run(
        tmp_path / "run",
        groups,
        50,
        lambda g, it: 0.76 if g == "finger_pull_door" else 0.9,
    )
    pad = [f"{it},/pad_enters_success/finger_pull_{kind},0.88" for it in range(50)
           for kind in ("drawer", "door", "flap")]  # fmt: skip
    header, *rows = (run / "metrics.csv").read_text().splitlines()
    rows = sorted(rows + pad, key=lambda row: int(row.split(",")[0]))  # one launch's order
    (run / "metrics.csv").write_text("\n".join([header, *rows]) + "\n")
    assert rule.last_window(run)["finger_pull_door"] == pytest.approx(0.76)
    assert rule.last_window(run, pad_enters=True)["finger_pull_door"] == pytest.approx(0.88)
    assert rule.last_window(run, pad_enters=True)["knob_door"] == pytest.approx(0.9)
    assert rule.main(["--mark", "0.8", str(run)]) == 1
    assert rule.main(["--mark", str(rule.MARKS[7]), "--pad-enters", str(run)]) == 0
    assert "adopted: yes" in capsys.readouterr().out
    # a run that never logged the tag fails the reading
    bare = write_run(tmp_path / "bare", groups, 50, lambda g, it: 1.0)
    assert rule.last_window(bare, pad_enters=True)["finger_pull_flap"] is None
