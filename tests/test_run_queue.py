"""The run queue (realikea/training/queue.py): resume from the last checkpoint, state, wall time,
keeping a finished run, and a failed one kept nowhere."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import threading
import time

from realikea.training import queue
from realikea.training.queue import QueuedRun, RunQueue


def _queue(tmp_path, kept: list[str]) -> RunQueue:
    def keep(run: QueuedRun, seconds: list[float]):
        kept.append(run.name)
        return tmp_path / "kept" / run.name

    return RunQueue(
        tmp_path / "work",
        lambda run: f"model_{run.iterations - 1}.pt",
        keep,
        lambda run: run.name in kept,
    )


RUN = QueuedRun("gated_hull_knob_smooth_s0", ("task/reward=gated", "asset=knob"), 400)


def test_a_stopped_run_continues_from_its_last_checkpoint(tmp_path):
    q = _queue(tmp_path, [])
    assert q.state(RUN) == "new" and not any("train.resume" in a for a in q.command(RUN))
    run_dir = tmp_path / "work" / RUN.name
    run_dir.mkdir(parents=True)
    for it in (0, 50, 150):
        (run_dir / f"model_{it}.pt").write_bytes(b"")
    command = q.command(RUN)
    assert command[2:4] == list(RUN.overrides)
    assert f"train.resume={run_dir / 'model_150.pt'}" in command
    assert "agent.max_iterations=250" in command  # 150 + 250 = the run's 400
    assert q.state(RUN) == "stopped"
    (tmp_path / "work" / f"{RUN.name}.pid").write_text("999999999\n")  # no such process
    assert q.state(RUN) == "stopped"
    (run_dir / "model_399.pt").write_bytes(b"")
    assert q.state(RUN) == "finished"


def test_a_finished_run_is_kept_and_a_failed_one_is_not(tmp_path, monkeypatch, capsys):
    kept: list[str] = []
    q = _queue(tmp_path, kept)
    monkeypatch.setattr(queue, "POLL_SECONDS", 0.2)
    done = tmp_path / "work" / RUN.name / "model_399.pt"
    wall = tmp_path / "work" / f"{RUN.name}.wall.json"
    # the "training" sleeps, prints its wall record mid-run and writes no last checkpoint
    script = f"import time; time.sleep(1.0); print(open({str(wall)!r}).read())"
    monkeypatch.setattr(RunQueue, "command", lambda self, run: [sys.executable, "-c", script])
    assert q.run_all([RUN], jobs=1) == 1 and kept == []
    assert "FAILED" in capsys.readouterr().out
    mid_run = json.loads((tmp_path / "work" / f"{RUN.name}.log").read_text())
    assert 0.1 < mid_run[0] < q.wall_times(RUN)[0]  # a stopped launch would still count
    # now it writes its last checkpoint: kept, with both launches' wall times
    done.parent.mkdir(parents=True)
    script = f"open({str(done)!r}, 'w').close()"
    assert q.run_all([RUN], jobs=1) == 0 and kept == [RUN.name]
    assert len(q.wall_times(RUN)) == 2 and q.state(RUN) == "kept"
    assert "min in 2 launches" in capsys.readouterr().out  # the whole wall time, not the last
    assert q.run_all([RUN], jobs=1) == 0 and "1 of 1 runs already kept" in capsys.readouterr().out


def test_a_run_whose_outcome_is_decided_is_interrupted_and_kept(tmp_path, monkeypatch, capsys):
    kept: list[str] = []
    q = _queue(tmp_path, kept)
    decided = tmp_path / "decided"
    q.stop_early = lambda run: decided.is_file()
    monkeypatch.setattr(queue, "POLL_SECONDS", 0.2)
    run_dir = tmp_path / "work" / RUN.name
    run_dir.mkdir(parents=True)
    # the "training" writes a checkpoint, decides its outcome and would then run for a minute;
    # on SIGINT it cleans up as train.py does (its finally closes the env pool), for 1.5 s
    script = (
        f"import pathlib, time\nopen({str(run_dir / 'model_120.pt')!r}, 'w').close()\n"
        f"pathlib.Path({str(decided)!r}).touch()\n"
        f"try:\n    time.sleep(60)\nfinally:\n    time.sleep(1.5)\n"
        f"    open({str(run_dir / 'closed')!r}, 'w').close()\n"
    )
    monkeypatch.setattr(RunQueue, "command", lambda self, run: [sys.executable, "-c", script])
    assert q.run_all([RUN], jobs=1) == 0 and kept == [RUN.name]
    assert "stopped gated_hull_knob_smooth_s0 early" in capsys.readouterr().out
    assert (run_dir / "closed").is_file() and (run_dir / queue.STOPPED_EARLY).is_file()
    assert 1.5 < q.wall_times(RUN)[0] < 30 and q.finished(RUN)  # counted up to the exit


def test_a_run_kept_by_another_driver_while_this_one_waited_is_not_kept_again(tmp_path, capsys):
    """Two drivers over one queue: this one listed the run as not kept, the other kept it
    before this one reached it; keeping it again would rewrite its committed checkpoint."""
    kept: list[str] = []
    asked: list[str] = []

    def kept_by_other(run: QueuedRun) -> bool:  # not kept when listed, kept from then on
        asked.append(run.name)
        return asked.count(run.name) > 1

    q = _queue(tmp_path, kept)
    q.kept = kept_by_other
    (tmp_path / "work" / RUN.name).mkdir(parents=True)
    (tmp_path / "work" / RUN.name / "model_399.pt").write_bytes(b"")  # finished
    assert q.run_all([RUN], jobs=1) == 0 and kept == []
    assert f"skip {RUN.name}: kept meanwhile" in capsys.readouterr().out


def test_a_parked_run_resumes_on_another_machine_from_its_last_checkpoint(tmp_path):
    q = _queue(tmp_path, [])
    q.parked = tmp_path / "parked"
    run_dir = tmp_path / "work" / RUN.name
    (run_dir / ".hydra").mkdir(parents=True)
    (run_dir / ".hydra" / "overrides.yaml").write_text("- asset=knob\n")
    (run_dir / "metrics.csv").write_text("iteration,tag,value\n0,Train/mean_reward,1.0\n")
    for it in (0, 150):
        (run_dir / f"model_{it}.pt").write_bytes(b"weights and optimiser %d" % it)
    (tmp_path / "work" / f"{RUN.name}.wall.json").write_text("[600.0]\n")
    (parked,) = q.park([RUN])
    assert sorted(p.name for p in parked.iterdir()) == [
        ".hydra", "metrics.csv", "model_150.pt", "wall.json"
    ]  # fmt: skip
    shutil.rmtree(tmp_path / "work")  # a new machine: the work folder is gone
    assert q.state(RUN) == "parked"
    q._unpark(RUN)
    assert q.state(RUN) == "stopped" and q.wall_times(RUN) == [600.0]
    assert f"train.resume={run_dir / 'model_150.pt'}" in q.command(RUN)
    assert (run_dir / "model_150.pt").read_bytes() == b"weights and optimiser 150"
    assert q.park([QueuedRun("never_started", (), 400)]) == []  # nothing to park


def test_a_staged_run_whose_stages_were_copied_in_but_never_launched_parks_and_resumes(tmp_path):
    """Stages copied from another run (no launch here, so no Hydra config or wall time) park
    like any stopped run, and resume from them on the next machine."""
    q = _queue(tmp_path, [])
    q.parked = tmp_path / "parked"
    run = QueuedRun("default_s201", (), 400, staged=True)
    run_dir = tmp_path / "work" / run.name
    (run_dir / "teacher_door").mkdir(parents=True)
    (run_dir / "teacher_door" / "metrics.csv").write_text("iteration,tag,value\n")
    (run_dir / "teacher_door" / "model_399.pt").write_bytes(b"door teacher")
    (run_dir / queue.STAGES).write_text('{"teacher_door": {}}\n')
    assert q.state(run) == "stopped"
    (parked,) = q.park([run])
    assert sorted(str(p.relative_to(parked)) for p in parked.rglob("*")) == [
        "stages.json", "teacher_door", "teacher_door/metrics.csv", "teacher_door/model_399.pt",
        "wall.json",
    ]  # fmt: skip
    assert json.loads((parked / "wall.json").read_text()) == []
    shutil.rmtree(tmp_path / "work")
    assert q.state(run) == "parked"
    q._unpark(run)
    assert q.state(run) == "stopped" and f"train.resume={run_dir}" in q.command(run)
    assert (run_dir / "teacher_door" / "model_399.pt").read_bytes() == b"door teacher"


def test_a_launch_that_died_before_its_first_checkpoint_starts_in_an_emptied_folder(
    tmp_path, monkeypatch
):
    """train.py refuses a folder holding another launch's metrics: the queue empties it."""
    q = _queue(tmp_path, [])
    run_dir = tmp_path / "work" / RUN.name
    run_dir.mkdir(parents=True)
    (run_dir / "metrics.csv").write_text("iteration,tag,value\n")
    monkeypatch.setattr(RunQueue, "command", lambda self, run: [sys.executable, "-c", "pass"])
    q._launch(RUN).wait()
    assert not run_dir.exists()


# a "training" that writes its config and metrics, then a checkpoint every TICK seconds (0, 50, ...
# and its last, ITERATIONS - 1), and exits 0 after its last; on SIGINT it cleans up as train.py
# does (its finally)
TICK = 0.6
TRAINING = """
import pathlib, sys, time
folder, iterations = pathlib.Path(sys.argv[1]), int(sys.argv[2])
(folder / ".hydra").mkdir(parents=True, exist_ok=True)
(folder / "metrics.csv").write_text("iteration,tag,value\\n")
try:
    for it in [*range(0, iterations - 1, 50), iterations - 1]:
        (folder / f"model_{it}.pt").touch()
        time.sleep(TICK)
finally:
    (folder / "closed").touch()
""".replace("TICK", str(TICK))


def _training(self, run):
    return [sys.executable, "-c", TRAINING, str(self.work / run.name), str(run.iterations)]


def _when(condition) -> None:
    deadline = time.time() + 30
    while not condition():
        assert time.time() < deadline
        time.sleep(0.02)


def test_parking_stops_each_run_at_its_next_checkpoint_and_launches_no_other(
    tmp_path, monkeypatch, capsys
):
    """The driver stops a run at the first checkpoint written after the request, lets one whose
    next checkpoint is its last finish (kept), launches no other run, and times each launch."""
    kept: list[str] = []
    q = _queue(tmp_path, kept)
    q.parked = tmp_path / "parked"
    monkeypatch.setattr(queue, "POLL_SECONDS", 0.1)
    monkeypatch.setattr(RunQueue, "command", _training)
    long, short, waiting = (QueuedRun("long", (), 300), QueuedRun("short", (), 51),
                            QueuedRun("waiting", (), 300))  # fmt: skip
    status: list[int] = []
    start = time.time()
    driver = threading.Thread(target=lambda: status.append(q.run_all([long, short, waiting], 2)))
    driver.start()
    _when(lambda: q.drivers() and q.last_checkpoint(long) == 0 and q.last_checkpoint(short) == 0)
    assert q.serve([long, short, waiting], 2, park=True) == 0
    driver.join()
    assert status == [0] and kept == ["short"]  # its next checkpoint was its last
    stopped_at = q.last_checkpoint(long)  # 50, or 100 if the driver saw the request late
    assert 0 < stopped_at < 299 and (tmp_path / "work" / "long" / "closed").is_file()
    assert not (tmp_path / "work" / "waiting.log").exists()
    (launch,) = q.wall_times(long)
    assert TICK < launch < time.time() - start
    assert sorted(p.name for p in q.parked.iterdir()) == ["long"]
    assert not (tmp_path / "work" / queue.PARK_REQUEST).exists() and q.drivers() == []
    assert f"stopped long at iteration {stopped_at}" in capsys.readouterr().out


def test_a_driver_of_several_stages_launches_no_later_stage_once_parked(tmp_path, monkeypatch):
    """A driver serving stages one run_all at a time (the generalist screen) stops at the park
    request and launches none of its later stages, though each begins after the request."""
    q = _queue(tmp_path, [])
    q.parked = tmp_path / "parked"
    monkeypatch.setattr(queue, "POLL_SECONDS", 0.1)
    monkeypatch.setattr(RunQueue, "command", _training)
    first, second = QueuedRun("first", (), 300), QueuedRun("second", (), 300)
    driver = threading.Thread(target=lambda: [q.run_all([run], 1) for run in (first, second)])
    driver.start()
    _when(lambda: q.drivers() and q.last_checkpoint(first) == 0)
    assert q.serve([first, second], 1, park=True) == 0
    driver.join()
    assert 0 < q.last_checkpoint(first) < 299 and not (tmp_path / "work" / "second.log").exists()
    assert sorted(p.name for p in q.parked.iterdir()) == ["first"]


def test_a_park_waits_for_a_driver_between_its_stages_and_no_later_stage_launches(
    tmp_path, monkeypatch
):
    """A driver holding `driving()` around its stages is a live driver between them (while it
    evaluates a kept run): a park made then waits for it, and its next stage launches nothing."""
    q = _queue(tmp_path, [])
    q.parked = tmp_path / "parked"
    monkeypatch.setattr(queue, "POLL_SECONDS", 0.1)
    monkeypatch.setattr(RunQueue, "command", _training)
    evaluated, later = threading.Event(), QueuedRun("later", (), 300)

    def drive() -> None:
        with q.driving():
            evaluated.wait(30)  # an evaluation between two stages
            q.run_all([later], 1)

    driver = threading.Thread(target=drive)
    driver.start()
    _when(lambda: q.drivers())
    parking = threading.Thread(target=lambda: q.serve([later], 1, park=True))
    parking.start()
    _when(lambda: (tmp_path / "work" / queue.PARK_REQUEST).is_file())
    assert parking.is_alive()  # it waits for the driver's block
    evaluated.set()
    driver.join()
    parking.join()
    assert not (tmp_path / "work" / "later.log").exists() and q.drivers() == []


def test_a_park_of_some_runs_neither_stops_nor_waits_for_a_driver_of_others(tmp_path, monkeypatch):
    """Two drivers on one work folder (the aims' recipes launched side by side): a park request
    naming only the other's runs leaves this driver's run training past its next checkpoints,
    and a park of this one's runs stops it without waiting for the other driver."""
    q = _queue(tmp_path, [])
    q.parked = tmp_path / "parked"
    monkeypatch.setattr(queue, "POLL_SECONDS", 0.1)
    monkeypatch.setattr(RunQueue, "command", _training)
    mine, theirs = QueuedRun("mine", (), 300), QueuedRun("theirs", (), 300)
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    try:
        drivers = tmp_path / "work" / queue.DRIVERS
        drivers.mkdir(parents=True)
        (drivers / str(other.pid)).write_text("theirs\n")  # another process driving `theirs`
        driver = threading.Thread(target=lambda: q.run_all([mine], 1))
        driver.start()
        _when(lambda: q.last_checkpoint(mine) == 0)
        assert q.drivers([mine]) == [os.getpid()] and q.drivers([theirs]) == [other.pid]
        request = tmp_path / "work" / queue.PARK_REQUEST
        request.write_text(f"{time.time()}\ntheirs\n")  # as a park of `theirs` asks
        _when(lambda: q.last_checkpoint(mine) >= 100)  # two checkpoints on: not stopped
        assert q.running(mine)
        assert q.serve([mine], 1, park=True) == 0  # returns with the other driver still alive
        driver.join()
        assert 0 < q.last_checkpoint(mine) < 299 and other.poll() is None
        assert sorted(p.name for p in q.parked.iterdir()) == ["mine"]
    finally:
        other.kill()


def test_a_stage_run_named_pipeline_slash_stage_launches_into_a_new_folder(tmp_path, monkeypatch):
    """A run named PIPELINE/STAGE (a distilled pipeline's teacher) launches before its
    pipeline's folder exists: its log and pid files go under it."""
    q = _queue(tmp_path, [])
    monkeypatch.setattr(RunQueue, "command", lambda self, run: [sys.executable, "-c", "pass"])
    proc = q._launch(QueuedRun("distilled_s20/teacher_drawer", (), 400))
    proc.wait()
    assert (tmp_path / "work/distilled_s20/teacher_drawer.log").is_file()


def test_parking_stops_a_run_whose_driver_died_and_times_its_launch(tmp_path, monkeypatch):
    """No live driver: the parking process stops the run at its next checkpoint itself and
    replaces the dead driver's last record of the launch with the launch's whole time."""
    q = _queue(tmp_path, [])
    q.parked = tmp_path / "parked"
    monkeypatch.setattr(queue, "POLL_SECONDS", 0.1)
    monkeypatch.setattr(RunQueue, "command", _training)
    run = QueuedRun("orphan", (), 300)
    proc = q._launch(run)
    reaper = threading.Thread(target=proc.wait)  # as init reaps a dead driver's child
    reaper.start()
    _when(lambda: q.last_checkpoint(run) == 0)
    (tmp_path / "work" / "orphan.wall.json").write_text("[500.0, 0.01]\n")  # its last poll
    assert q.serve([run], 1, park=True) == 0
    reaper.join()
    assert proc.returncode != 0 and 0 < q.last_checkpoint(run) < 299
    earlier, launch = q.wall_times(run)
    assert earlier == 500.0 and TICK < launch < 10
    assert (q.parked / "orphan" / f"model_{q.last_checkpoint(run)}.pt").is_file()
