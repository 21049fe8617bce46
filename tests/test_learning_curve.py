"""A run's learning curve (realikea/reports/learning_curve.py): a panel per category x kind only
for runs that log per-group success, one of envs per group for runs whose draw follows success,
written where asked."""

from __future__ import annotations

from PIL import Image

from realikea.reports.learning_curve import plot_learning_curve

TAGS = ("/episode/success", "/episode/partial", "/episode/fail", "/episode/opening",
        "Train/mean_reward")  # fmt: skip


def _run(run_dir, groups: tuple[str, ...]):
    """A 30-iteration run's metrics.csv in a new `run_dir`, with the given per-group tags."""
    run_dir.mkdir()
    rows = ["iteration,tag,value"]
    for it in range(30):
        rows += [f"{it},{tag},{it / 30:.3f}" for tag in (*TAGS, *groups)]
    (run_dir / "metrics.csv").write_text("\n".join(rows) + "\n")
    return run_dir


def test_a_generalists_curve_has_a_panel_per_group_and_a_specialists_does_not(tmp_path):
    generalist = _run(tmp_path / "g", ("/success/knob_drawer", "/success/two_point_door"))
    specialist = _run(tmp_path / "s", ())
    wide = plot_learning_curve(generalist)
    assert wide == generalist / "learning_curve.png"
    narrow = plot_learning_curve(specialist, tmp_path / "elsewhere.png")
    assert narrow == tmp_path / "elsewhere.png" and not (specialist / "learning_curve.png").exists()
    assert Image.open(wide).size == (2000, 400)  # four panels, 20 x 4 in at 100 dpi
    assert Image.open(narrow).size == (1500, 400)  # three


def test_a_run_whose_draw_follows_success_gets_a_panel_of_envs_per_group(tmp_path):
    run = _run(tmp_path / "f", ("/success/knob_drawer", "/draw/knob_drawer"))
    assert Image.open(plot_learning_curve(run)).size == (2500, 400)  # five panels
