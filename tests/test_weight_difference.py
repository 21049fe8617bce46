"""Two checkpoints' actors compared, and a kept run's copied stage folders found and removed
(experiments/tools/weight_difference.py)."""

from __future__ import annotations

import pytest
import torch


@pytest.fixture
def weights(load_script):
    return load_script("experiments/tools/weight_difference.py")


def save(path, shift: float = 0.0, count: float = 10.0, width: int = 3):
    path.parent.mkdir(parents=True, exist_ok=True)
    actor = {
        "mlp.0.weight": torch.ones(2, width) + shift,
        "obs_normalizer.count": torch.tensor(count),
    }
    torch.save({"actor_state_dict": actor, "iter": 1}, path)
    return path


def test_the_network_and_the_normaliser_are_told_apart(weights, tmp_path, capsys):
    a = save(tmp_path / "a.pt")
    b = save(tmp_path / "b.pt", shift=0.25, count=30.0)
    assert weights.main([str(a), str(b)]) == 0
    assert "max |Δw| 0.25 over the network, 20 over the normaliser" in capsys.readouterr().out


def test_actors_of_different_layouts_are_refused(weights, tmp_path, capsys):
    a, b = save(tmp_path / "a.pt"), save(tmp_path / "b.pt", width=4)
    assert weights.main([str(a), str(b)]) == 2
    assert "the actors' layouts differ" in capsys.readouterr().err


def test_only_exact_copies_are_removed_once_every_stage_is_compared(weights, tmp_path, capsys):
    source, run = tmp_path / "source", tmp_path / "run"
    for folder in (source, run):
        save(folder / "teacher_door/model_399.pt")  # a copy
        (folder / "teacher_door/metrics.csv").write_text("it\n")
    save(source / "teacher_flap/model_399.pt")
    save(run / "teacher_flap/model_399.pt", shift=0.1)  # retrained since
    save(run / "teacher_knob_door_retrain/model_399.pt")  # new
    args = ["--stages", str(run), str(source), "--remove-copies"]
    assert weights.main(args) == 0
    out = capsys.readouterr().out
    assert "teacher_door: max |Δw| 0 against" in out and "removed" in out
    assert "teacher_flap: max |Δw| 0.1 against" in out
    assert "teacher_knob_door_retrain: new (no source has it); kept" in out
    assert sorted(p.name for p in run.iterdir()) == ["teacher_flap", "teacher_knob_door_retrain"]


def test_a_later_source_is_the_one_compared(weights, tmp_path):
    first, second, run = tmp_path / "first", tmp_path / "second", tmp_path / "run"
    save(first / "teacher_door/model_399.pt", shift=1.0)
    save(second / "teacher_door/model_399.pt")
    save(run / "teacher_door/model_399.pt")
    lines = weights.compare_stages(run, [first, second], remove=False)
    assert lines == [f"teacher_door: max |Δw| 0 against {second / 'teacher_door'} "
                     "(every actor tensor); a copy"]  # fmt: skip
    assert (run / "teacher_door").is_dir()


@pytest.mark.parametrize(
    ("args", "refusal"),
    [
        (["a.pt"], "give two checkpoints"),
        (["a.pt", "absent.pt"], "no such checkpoint: absent.pt"),
        (["a.pt", "b.pt", "--remove-copies"], "--remove-copies goes with --stages"),
        (["--stages", "run", "absent"], "no such run folder: absent"),
    ],
)
def test_bad_input_is_refused_before_anything_is_read(
    weights, tmp_path, monkeypatch, capsys, args, refusal
):
    monkeypatch.chdir(tmp_path)
    save(tmp_path / "a.pt"), save(tmp_path / "b.pt")
    save(tmp_path / "run/teacher_door/model_1.pt")
    monkeypatch.setattr(weights, "load_saved", lambda p: pytest.fail("a checkpoint was read"))
    with pytest.raises(SystemExit) as exit_:
        weights.main(args)
    assert exit_.value.code == 2
    assert refusal in capsys.readouterr().err
    assert (tmp_path / "run/teacher_door").is_dir()
