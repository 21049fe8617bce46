"""How likely the aims' verdicts are to repeat (experiments/generalist/aim_chance.py): the binomial
and beta-binomial tails held to the aims' marks, and each kept seed's chance from its cells."""

from __future__ import annotations

import sys

import pytest


@pytest.fixture
def chance(load_script, monkeypatch, tmp_path):
    module = load_script("experiments/generalist/aim_chance.py")
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    monkeypatch.setattr(sys.modules["aims_report"], "HULL_FP_DOOR", tmp_path / "hull_fp_door")
    return module


def test_a_mark_needs_its_successes_without_float_error(chance):
    assert chance.needed(0.7, 50) == 35 and chance.needed(0.8, 50) == 40
    assert chance.needed(0.8, 49) == 40  # 39.2 rounds up


def test_a_policy_at_its_mark_in_one_cell_passes_about_half_the_time(chance):
    # P(Bin(50, 0.8) >= 40) = 0.5836 (a tail of the binomial, by hand: sum_k C(50,k) .8^k .2^(50-k))
    one = chance.same_rate_chance(0.8, {"smooth": 0.8}, 1, 50)
    assert one == pytest.approx(0.5836, abs=1e-4)
    assert chance.same_rate_chance(0.8, {"smooth": 0.8}, 9, 50) == pytest.approx(one**9)
    assert chance.same_rate_chance(1.0, {"smooth": 0.8, "high": 0.7}, 9, 50) == 1.0


def test_a_fresh_read_is_likelier_to_pass_the_higher_the_cell_read(chance):
    reads = [chance.fresh_read_chance(k, 50, 0.8, 50) for k in (30, 40, 45, 50)]
    assert reads == sorted(reads) and reads[0] < 0.05 and reads[-1] > 0.95
    assert 0.4 < reads[1] < 0.7  # a read at the mark: about a coin toss


def test_each_kept_seed_gets_its_chance_and_its_least_likely_cells(chance, tmp_path, write_cells):
    write_cells(
        tmp_path / "default/s200", ("smooth", "high"), 0.96, low=("door", "knob", "high", 0.68)
    )
    write_cells(tmp_path / "default/s201", ("smooth", "high"), 1.0)
    write_cells(tmp_path / "default/s202", ("smooth",), 1.0)  # its high cells not yet evaluated
    chance.main([])
    text = (tmp_path / "aim_chance.md").read_text()
    assert "| s200 | missed |" in text and "knob doors high 34/50" in text.split("| s200 |")[1]
    assert "| s201 | met | 1.00 |" in text
    assert "| s202 | not all cells evaluated |" in text
    assert "| s210 | not evaluated |" in text
    with pytest.raises(SystemExit):
        chance.main(["--episodes", "0"])


def test_a_superseded_recipes_runs_are_read_from_their_own_folder(chance, tmp_path, write_cells):
    write_cells(tmp_path / "default_old/s200", ("smooth", "high"), 1.0)
    chance.main(["--superseded", "old"])
    text = (tmp_path / "aim_chance_old.md").read_text()
    assert "`default_old`" in text and "| s200 | met | 1.00 |" in text
    assert not (tmp_path / "aim_chance.md").exists()
    with pytest.raises(SystemExit):
        chance.main(["--superseded", "none_such"])
