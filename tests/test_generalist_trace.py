"""One episode step by step (experiments/generalist/trace.py): a scripted pull traced end to end,
and a bad index refused before any work."""

from __future__ import annotations

import pytest

# one 10 s episode of the heuristic pull on one configuration: it pinches the bar open
PIN = "asset=two_point asset.part=tp_round_bar_128 asset.base=drawer_w60_h20"
OVERRIDES = [
    "policy=heuristic_pull", *PIN.split(), "asset.split=train", "dr=fixed", "env.seed=3",
    "task.episode_seconds=10",
]  # fmt: skip


@pytest.fixture
def trace(load_script):
    return load_script("experiments/generalist/trace.py")


def test_a_scripted_pull_is_traced_step_by_step_into_markdown(trace, tmp_path, capsys):
    out = tmp_path / "trace.md"
    library = f"paths.library={tmp_path / 'library'}"
    assert trace.main(["--episode", "0", "--out", str(out), *OVERRIDES, library]) == 0
    text = out.read_text()
    assert text.startswith("# tp_round_bar_128__drawer_w60_h20: one episode, step by step")
    assert "Ended: success" in text
    rows = [line for line in text.splitlines() if line.startswith("| ") and line[2].isdigit()]
    assert len(rows) == 100  # 10 s at 10 Hz, one row a step
    first, last = rows[0].split(" | "), rows[-1].split(" | ")
    assert first[0] == "| 0" and last[0] == "| 99"
    assert float(last[1]) >= 0.2  # the drawer opened past the success mark
    assert last[2] == "4"  # still engaged at the end ...
    assert last[3] == "left right"  # ... pinched: both fingers on the bar
    assert "written:" in capsys.readouterr().out


def test_a_negative_episode_is_refused_before_any_work(trace, monkeypatch, capsys):
    monkeypatch.setattr(trace, "eval_setup", lambda *a: pytest.fail("work started"))
    with pytest.raises(SystemExit) as exit_:
        trace.main(["--episode", "-1", *OVERRIDES])
    assert exit_.value.code == 2
    assert "--episode -1: use 0 or more" in capsys.readouterr().err
