"""A training launch's inputs are checked before Hydra writes its folder: settings out of range
are refused by name, a folder holding another run is refused, errors print one line."""

from __future__ import annotations

import subprocess
import sys

import pytest

from realikea.config import check_settings, load_config
from realikea.errors import RealIkeaError
from realikea.files import WORKSPACE
from realikea.training.preflight import check_fresh_folder, user_errors

SMALL = ["asset=two_point", "asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20"]


def _train(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "train.py", *SMALL, "logger=none", *args],
        cwd=WORKSPACE,
        capture_output=True,
        text=True,
    )


@pytest.mark.parametrize(
    "override, message",
    [
        ("agent.max_iterations=-3", "agent.max_iterations=-3: use an integer >= 1"),
        ("env.num_envs=0", "env.num_envs=0: use an integer >= 1"),
        ("agent.save_interval=0", "agent.save_interval=0: use an integer >= 1"),
        ("agent.num_steps_per_env=2.5", "agent.num_steps_per_env=2.5: use an integer >= 1"),
        ("env.num_workers=-1", "env.num_workers=-1: use an integer >= 0"),
        ("dr.switch_iteration=-1", "dr.switch_iteration=-1: use an integer >= 0"),
        ("env.step_timeout=0", "env.step_timeout=0: use a number > 0"),
        ("+train.eval_after.episodes=0", "train.eval_after.episodes=0: use an integer >= 1"),
    ],
)
def test_a_setting_out_of_range_is_refused_by_name(override, message):
    with pytest.raises(RealIkeaError, match=message.replace(".", r"\.").replace("+", r"\+")):
        check_settings(load_config([override]))


def test_the_defaults_and_a_null_worker_count_pass():
    check_settings(load_config(["env.num_workers=null"]))
    check_settings(load_config([], "eval"))


def test_eval_refuses_zero_episodes_by_name():
    with pytest.raises(RealIkeaError, match="episodes=0: use an integer >= 1"):
        check_settings(load_config(["episodes=0"], "eval"))


def test_negative_iterations_exit_2_with_one_line_and_write_nothing(tmp_path):
    out = _train("agent.max_iterations=-3", f"hydra.run.dir={tmp_path / 'run'}")
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == [
        "train: error: agent.max_iterations=-3: use an integer >= 1"
    ]
    assert not (tmp_path / "run").exists()


def test_a_second_launch_into_a_run_folder_is_refused_and_leaves_it_as_it_was(tmp_path):
    run = tmp_path / "run"
    (run / ".hydra").mkdir(parents=True)
    files = {
        "metrics.csv": "iteration,tag,value\n0,Train/mean_reward,1.0\n",
        "model_0.pt": "weights",
        "model_10.pt": "weights",
        ".hydra/config.yaml": "the first launch's config\n",
    }
    for name, text in files.items():
        (run / name).write_text(text)
    out = _train(f"hydra.run.dir={run}")
    assert out.returncode == 2
    (line,) = out.stderr.strip().splitlines()
    assert f"{run} already holds a run" in line
    assert f"train.resume={run / 'model_10.pt'}" in line and f"hydra.run.dir={run}_2" in line
    assert {name: (run / name).read_text() for name in files} == files
    assert sorted(p.name for p in run.iterdir()) == [".hydra", "metrics.csv", *sorted(files)[2:]]


def test_a_resumed_launch_and_an_empty_folder_pass(tmp_path):
    (tmp_path / "metrics.csv").write_text("iteration,tag,value\n")
    check_fresh_folder(tmp_path, resume=str(tmp_path / "model_0.pt"))
    check_fresh_folder(tmp_path / "new", resume=None)
    with pytest.raises(RealIkeaError, match="a fresh folder"):
        check_fresh_folder(tmp_path, resume=None)


def test_a_user_error_is_one_line_and_its_trace_only_on_request(capsys, monkeypatch):
    monkeypatch.delenv("HYDRA_FULL_ERROR", raising=False)
    with pytest.raises(SystemExit) as stop, user_errors():
        raise RealIkeaError("unknown base kind 'window'")
    assert stop.value.code == 2
    assert capsys.readouterr().err == "train: error: unknown base kind 'window'\n"
    monkeypatch.setenv("HYDRA_FULL_ERROR", "1")
    with pytest.raises(RealIkeaError, match="window"), user_errors():
        raise RealIkeaError("unknown base kind 'window'")
