"""Training runs as `train.py` processes, a few at a time, each resumable and kept when done.

A run trains in WORK/NAME (git-ignored). It is finished once WORK/NAME holds its `done` file
(e.g. eval.json, or the last checkpoint), and
then kept: `keep(run, seconds)` copies what the experiment commits. A stopped run (checkpoints,
no `done` file) continues from its last checkpoint (`train.resume=`) for the iterations it
still lacks, appending to its metrics.csv; one without a checkpoint starts again in an emptied
folder (train.py refuses a folder that holds another launch's files). A staged run (a training
pipeline: realikea/training/pipeline.py, its stages in folders of WORK/NAME) continues from its
folder (`train.resume=WORK/NAME`), which finds its stages done or stopped. A run whose training
process is alive (WORK/NAME.pid) is left to it, so two drivers never train the same run, and one
kept meanwhile by another driver is not kept again. Each launch's wall time is written to
WORK/NAME.wall.json at every poll, so a launch stopped with the session still counts. A run whose
outcome is decided before its last iteration (`stop_early(run)`, checked at every poll) is
interrupted (SIGINT: the trainer closes its env pool), marked finished (WORK/NAME/STOPPED_EARLY)
and kept with its last checkpoint. WORK is gone with the machine: `park` copies each stopped
run's resumable state to a folder git holds, and a later launch of it starts from there.

At a session's end `serve(park=True)` stops the runs at their next checkpoints and parks them: it
asks the live drivers of those runs (WORK/drivers/PID names the runs a driver drives, or none: any
run) through WORK/PARK, which names the runs, and each stops launching (in its
later run_all calls too: a driver of several stages runs no later stage, and one holding
`driving()` around its stages is waited for to the block's end), interrupts
every run once it has written a checkpoint after the request (a run past its last checkpoint
finishes and is kept), records the launch's wall time and exits; a run training with no live
driver is stopped the same way by the parking process itself, its launch timed from its pid file.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from realikea.eval.sweep import checkpoints
from realikea.files import WORKSPACE, atomic_write_text
from realikea.policies.checkpoint import slim_checkpoint
from realikea.training.metrics import join_launches

POLL_SECONDS = 10.0  # how often the driver checks its runs and records their wall time
STOPPED_EARLY = "STOPPED_EARLY"  # in a run's folder: stopped by `stop_early`, finished as it is
PARK_REQUEST = "PARK"  # in WORK: its time, then the runs to stop at their next checkpoints
DRIVERS = "drivers"  # in WORK: a file per live driver, named by its pid, naming its runs (or none)
STAGES = "stages.json"  # in a staged run's folder: its finished stages (training/pipeline.py)


@dataclass(frozen=True)
class QueuedRun:
    """One training run: its name (its folder), train.py overrides and length (a staged run's:
    its last stage's, whose checkpoints are in its folder itself)."""

    name: str
    overrides: tuple[str, ...]
    iterations: int
    staged: bool = field(default=False, kw_only=True)  # keyword-only: subclasses add positionals


@dataclass
class RunQueue:
    """Where runs train (`work`), what marks one finished (`done(run)`: a file name in its run
    directory), how a finished one is kept (`keep(run, launch seconds)` -> where), whether it
    is (`kept(run)`) and whether a running one may stop now (`stop_early(run)`)."""

    work: Path
    done: Callable[[QueuedRun], str]
    keep: Callable[[QueuedRun, list[float]], Path]
    kept: Callable[[QueuedRun], bool]
    stop_early: Callable[[QueuedRun], bool] = lambda run: False
    parked: Path | None = None  # where `park` leaves stopped runs for a later machine (in git)
    # as a driver: when it began driving, how deep in `driving` blocks it is, and whether it
    # has seen a park request since (then none of its later run_all calls launches a run)
    _driving_since: float | None = field(default=None, init=False, repr=False)
    _driving_depth: int = field(default=0, init=False, repr=False)
    _park_seen: bool = field(default=False, init=False, repr=False)
    # the runs it drives (None: any, a block that named none)
    _driving_names: set[str] | None = field(default_factory=set, init=False, repr=False)

    def command(self, run: QueuedRun) -> list[str]:
        """The train.py command of `run`, continuing from its last checkpoint if it has one."""
        out = [sys.executable, str(WORKSPACE / "train.py"), *run.overrides]
        out.append(f"hydra.run.dir={self.work / run.name}")
        if run.staged:
            return out + ([f"train.resume={self.work / run.name}"] if self.progress(run) else [])
        if (found := self._last_checkpoint(run)) is not None:
            last, path = found
            out += [f"train.resume={path}", f"agent.max_iterations={run.iterations - last}"]
        return out

    def running(self, run: QueuedRun) -> bool:
        """Whether a training process of `run` (its pid file) is alive."""
        pid_file = self.work / f"{run.name}.pid"
        return pid_file.is_file() and _alive(pid_file.read_text())

    def state(self, run: QueuedRun) -> str:
        """kept, running, finished (not yet kept), stopped (has checkpoints), parked (stopped
        on another machine: `park`) or new."""
        if self.kept(run):
            return "kept"
        if self.running(run):
            return "running"
        if self.finished(run):
            return "finished"
        if self.progress(run) > 0:
            return "stopped"
        parked = self.parked is not None and (self.parked / run.name / "wall.json").is_file()
        return "parked" if parked else "new"

    def finished(self, run: QueuedRun) -> bool:
        run_dir = self.work / run.name
        return (run_dir / self.done(run)).is_file() or (run_dir / STOPPED_EARLY).is_file()

    def _last_checkpoint(self, run: QueuedRun) -> tuple[int, Path] | None:
        """The run's last checkpoint in `work` (iteration, path), or None."""
        if not any((self.work / run.name).glob("model_*.pt")):
            return None
        return checkpoints(self.work / run.name)[-1]

    def last_checkpoint(self, run: QueuedRun) -> int:
        """The iteration of the run's last checkpoint in `work` (-1: none)."""
        found = self._last_checkpoint(run)
        return -1 if found is None else found[0]

    def progress(self, run: QueuedRun) -> int:
        """What grows with each checkpoint the run writes (0: none yet): its last checkpoint's
        iteration + 1, or a staged run's count of checkpoints over its stages."""
        if run.staged:
            return sum(1 for _ in (self.work / run.name).rglob("model_*.pt"))
        return self.last_checkpoint(run) + 1

    def may_stop(self, run: QueuedRun, since: int) -> bool:
        """Whether to stop `run` for parking: it has written a checkpoint since its `progress`
        was `since`, and not its last (a run past its last checkpoint is evaluating: it
        finishes)."""
        final = self.work / run.name / f"model_{run.iterations - 1}.pt"
        return since < self.progress(run) and not final.is_file()

    def wall_times(self, run: QueuedRun) -> list[float]:
        """Wall seconds of the run's launches so far (the running one's as of the last poll)."""
        path = self._wall_path(run)
        return json.loads(path.read_text()) if path.is_file() else []

    def _wall_path(self, run: QueuedRun) -> Path:
        return self.work / f"{run.name}.wall.json"

    def _record_wall(self, run: QueuedRun, seconds: list[float]) -> None:
        """Write the wall seconds of the run's launches (the last one: so far)."""
        atomic_write_text(self._wall_path(run), json.dumps(seconds) + "\n")

    def park(self, runs: list[QueuedRun]) -> list[Path]:
        """Copy each stopped run's resumable state to `parked`/NAME: its Hydra config (if it was
        launched here), metrics, last checkpoint whole (optimiser included; a staged run: each
        stage's metrics and last checkpoint, and its stages.json) and launches' wall times, so a
        session on another machine resumes it (`_launch` puts it back); returns the folders
        written."""
        if self.parked is None:
            raise ValueError("this queue has no folder to park runs in")
        done = []
        for run in runs:
            if self.state(run) != "stopped":
                continue
            source, target = self.work / run.name, self.parked / run.name
            staging = target.with_name(target.name + ".partial")
            shutil.rmtree(staging, ignore_errors=True)
            staging.mkdir(parents=True)
            if (source / ".hydra").is_dir():  # absent: stages copied in, never launched here
                shutil.copytree(source / ".hydra", staging / ".hydra")
            for folder in _trained_folders(source, run.staged):
                target_folder = staging / folder.relative_to(source)
                target_folder.mkdir(parents=True, exist_ok=True)
                shutil.copy2(folder / "metrics.csv", target_folder / "metrics.csv")
                last = checkpoints(folder)[-1][1]
                shutil.copy2(last, target_folder / last.name)
            if run.staged and (source / STAGES).is_file():
                shutil.copy2(source / STAGES, staging / STAGES)
            atomic_write_text(staging / "wall.json", json.dumps(self.wall_times(run)) + "\n")
            shutil.rmtree(target, ignore_errors=True)
            staging.rename(target)
            done.append(target)
        return done

    def _unpark(self, run: QueuedRun) -> None:
        """Put a parked run back in `work` (its wall times too) to resume it there."""
        source, target = self.parked / run.name, self.work / run.name
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(source, target, ignore=shutil.ignore_patterns("wall.json"))
        shutil.copy2(source / "wall.json", self._wall_path(run))

    def _launch(self, run: QueuedRun) -> subprocess.Popen:
        self.work.mkdir(parents=True, exist_ok=True)
        state = self.state(run)
        if state == "new" and any((self.work / run.name).rglob("metrics.csv")):
            shutil.rmtree(self.work / run.name)  # a launch that died before its first checkpoint
        if state == "parked":
            self._unpark(run)
        log_path = self.work / f"{run.name}.log"
        log_path.parent.mkdir(parents=True, exist_ok=True)  # a stage's run: PIPELINE/STAGE
        log = log_path.open("a")
        command = self.command(run)
        print(f"start {run.name}: {' '.join(command[1:])}", flush=True)
        proc = subprocess.Popen(
            command, cwd=WORKSPACE, stdout=log, stderr=subprocess.STDOUT, preexec_fn=_interruptible
        )
        atomic_write_text(self.work / f"{run.name}.pid", f"{proc.pid}\n")
        return proc

    def _stop(self, run: QueuedRun, proc: subprocess.Popen, begin: float, seconds: list[float]):
        """SIGINT a launch and wait for it to exit; its wall time counts up to the exit."""
        proc.send_signal(signal.SIGINT)
        proc.wait()
        seconds[-1] = time.time() - begin
        self._record_wall(run, seconds)

    def show(self, runs: list[QueuedRun]) -> None:
        """Print each run's state and the command a launch would run now (a dry run)."""
        for run in runs:
            print(f"{self.state(run)}: " + " ".join(self.command(run)[1:]))

    def serve(self, runs: list[QueuedRun], jobs: int, dry_run: bool = False, park: bool = False):
        """A driver's command on its runs: print them (`dry_run`), stop them at their next
        checkpoints and park them (`park`), or train them `jobs` at a time (`run_all`); returns
        the exit status."""
        if dry_run:
            self.show(runs)
            return 0
        if park:
            self.stop_at_checkpoints(runs)
            for folder in self.park(runs):
                print(f"parked {folder}")
            return 0
        return self.run_all(runs, jobs)

    def drivers(self, runs: list[QueuedRun] | None = None) -> list[int]:
        """The pids of the live drivers of this queue (of any of `runs`, when given: those
        naming one of them or naming none)."""
        folder = self.work / DRIVERS
        found = [p for p in folder.glob("*") if _alive(p.name)] if folder.is_dir() else []
        if runs is not None:
            asked = {run.name for run in runs}
            found = [p for p in found if _drives(p, asked)]
        return [int(p.name) for p in found]

    def stop_at_checkpoints(self, runs: list[QueuedRun]) -> None:
        """Stop every training run of `runs` at its next checkpoint: through its driver if one
        is alive (a driver of other runs goes on), else here (a run whose driver died),
        recording the launch's wall time; returns once none of them is left training."""
        request = self.work / PARK_REQUEST
        if self.drivers(runs):
            names = "".join(f"{run.name}\n" for run in runs)
            atomic_write_text(request, f"{time.time()}\n{names}")
            print(f"asked drivers {self.drivers(runs)} to stop runs at next checkpoints",
                  flush=True)  # fmt: skip
            while self.drivers(runs):
                time.sleep(POLL_SECONDS)
        orphans = {run: self.progress(run) for run in runs if self.running(run)}
        for run in orphans:
            print(f"{run.name} trains with no driver: stop at next checkpoint", flush=True)
        while orphans:
            time.sleep(POLL_SECONDS)
            for run, since in list(orphans.items()):
                if self.running(run) and not self.may_stop(run, since):
                    continue
                pid_file = self.work / f"{run.name}.pid"
                if self.running(run):
                    os.kill(int(pid_file.read_text()), signal.SIGINT)
                    while self.running(run):
                        time.sleep(0.1)
                self._record_orphan_launch(run, time.time() - pid_file.stat().st_mtime)
                del orphans[run]
        request.unlink(missing_ok=True)

    def _record_orphan_launch(self, run: QueuedRun, seconds: float) -> None:
        """Write a launch's wall time in place of what its dead driver last recorded of it."""
        times = self.wall_times(run)
        launched = (self.work / f"{run.name}.pid").stat().st_mtime
        if times and self._wall_path(run).stat().st_mtime >= launched:
            times.pop()  # the dead driver's last poll of this launch
        self._record_wall(run, [*times, seconds])
        print(f"stopped {run.name} at iteration {self.last_checkpoint(run)}", flush=True)

    @contextmanager
    def driving(self, runs: list[QueuedRun] | None = None) -> Iterator[None]:
        """This process is a live driver of the queue's `runs` (None: any) for the block
        (WORK/drivers/PID): a driver that serves several stages with work between them (an
        evaluation) holds the block around them all, so a park of its runs waits for the whole
        block and no later stage launches."""
        me = self.work / DRIVERS / str(os.getpid())
        me.parent.mkdir(parents=True, exist_ok=True)
        if runs is None or self._driving_names is None:
            self._driving_names = None
        else:
            self._driving_names |= {run.name for run in runs}
        atomic_write_text(me, "".join(f"{name}\n" for name in sorted(self._driving_names or ())))
        if self._driving_since is None:
            self._driving_since = time.time()
        self._driving_depth += 1
        try:
            yield
        finally:
            self._driving_depth -= 1
            if not self._driving_depth:
                me.unlink(missing_ok=True)
                self._driving_names = set()

    def run_all(self, runs: list[QueuedRun], jobs: int) -> int:
        """Launch the runs `jobs` at a time, keep each that finishes; 1 if any failed."""
        with self.driving(runs):
            return self._drive(runs, jobs)

    def _parking(self) -> bool:
        """Whether a park request of one of this driver's runs was made since it began driving
        (an older one is left over from a parking process that died)."""
        request = self.work / PARK_REQUEST
        try:  # a park of other runs removes its request when they are parked
            made, text = request.stat().st_mtime, request.read_text()
        except FileNotFoundError:
            return self._park_seen
        if made >= self._driving_since:
            asked, mine = _names(text.partition("\n")[2]), self._driving_names
            self._park_seen |= mine is None or not asked or bool(asked & mine)
        return self._park_seen

    def _drive(self, runs: list[QueuedRun], jobs: int) -> int:
        queue = [r for r in runs if not self.kept(r)]
        print(f"{len(runs) - len(queue)} of {len(runs)} runs already kept; {len(queue)} to go")
        active: dict[QueuedRun, tuple[subprocess.Popen, float, list[float]]] = {}
        stop_after: dict[QueuedRun, int] | None = None  # parking: last checkpoints at the request
        failed = 0
        while active or (queue and stop_after is None):
            if stop_after is None and self._parking():
                stop_after = {run: self.progress(run) for run in active}
                print("parking: each run stops at its next checkpoint", flush=True)
            while queue and len(active) < jobs and stop_after is None:
                run = queue.pop(0)
                if self.kept(run):  # by another driver while this one waited
                    print(f"skip {run.name}: kept meanwhile", flush=True)
                    continue
                if self.running(run):
                    print(f"skip {run.name}: being trained by another process", flush=True)
                    continue
                if self.finished(run):  # finished, not kept
                    print(f"kept {self.keep(run, self.wall_times(run))}", flush=True)
                    continue
                active[run] = (self._launch(run), time.time(), self.wall_times(run))
            time.sleep(POLL_SECONDS)
            for run, (proc, begin, earlier) in list(active.items()):
                seconds = [*earlier, time.time() - begin]
                self._record_wall(run, seconds)
                stopped = False
                if proc.poll() is None:
                    if stop_after is not None and self.may_stop(run, stop_after[run]):
                        self._stop(run, proc, begin, seconds)
                        at = self.last_checkpoint(run)
                        print(f"stopped {run.name} at iteration {at}", flush=True)
                        del active[run]
                        continue
                    if not self.stop_early(run):
                        continue
                    self._stop(run, proc, begin, seconds)
                    atomic_write_text(
                        self.work / run.name / STOPPED_EARLY, f"exit {proc.returncode}\n"
                    )
                    print(f"stopped {run.name} early: its outcome is decided", flush=True)
                    stopped = True
                del active[run]
                if self.finished(run) and (proc.returncode == 0 or stopped):
                    kept = self.keep(run, seconds)
                    launches = f"{len(seconds)} launch{'es' if len(seconds) > 1 else ''}"
                    minutes = f"{sum(seconds) / 60:.1f} min in {launches}"
                    print(
                        f"kept {kept} ({minutes}, {seconds[-1] / 60:.1f} min the last)", flush=True
                    )
                else:
                    failed += 1
                    print(f"FAILED {run.name} (exit {proc.returncode}): {self.work / run.name}.log")
        return 1 if failed else 0


def _drives(driver: Path, asked: set[str]) -> bool:
    """Whether the driver whose file this is drives one of the `asked` runs (its file names
    one, or none: any run); a file gone meanwhile (its driver exited) drives none."""
    try:
        names = _names(driver.read_text())
    except FileNotFoundError:
        return False
    return not names or bool(names & asked)


def _names(text: str) -> set[str]:
    """The run names of a driver's file or a park request's lines."""
    return {line for line in text.splitlines() if line}


def _alive(pid: str) -> bool:
    """Whether a process with this pid (text) is alive."""
    try:
        os.kill(int(pid), 0)
    except (ProcessLookupError, ValueError):
        return False
    return True


def _interruptible() -> None:
    """In a launched run: SIGINT's default disposition, which a driver started in the background
    (`&`, nohup) passes on as ignored, so Python turns SIGINT into KeyboardInterrupt."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _trained_folders(run_dir: Path, staged: bool) -> list[Path]:
    """The folders of a run that hold a training's metrics and checkpoints: the run's, and a
    staged run's stages' (its folders holding checkpoints)."""
    stages = sorted({p.parent for p in run_dir.glob("*/model_*.pt")}) if staged else []
    return [run_dir, *stages] if any(run_dir.glob("model_*.pt")) else stages


def keep_run(
    source: Path,
    target: Path,
    seconds: list[float],
    kept: list[Path] | None = None,
    files: dict[str, str] | None = None,
    staged: bool = False,
) -> Path:
    """Copy a finished run's Hydra config, its metrics (launches joined), its checkpoints
    `kept` (default: the last) slimmed to what evaluation reads, the launches' wall times and
    `files` (name -> text) from `source` to `target`, which appears whole or not at all. A
    `staged` run's stages come too, each its metrics and last checkpoint slimmed, and its
    stages.json."""
    staging = target.with_name(target.name + ".partial")
    shutil.rmtree(staging, ignore_errors=True)
    shutil.copytree(source / ".hydra", staging / ".hydra")
    for name, text in (files or {}).items():
        atomic_write_text(staging / name, text)
    for folder in _trained_folders(source, staged):
        target_folder = staging / folder.relative_to(source)
        target_folder.mkdir(parents=True, exist_ok=True)
        metrics = (folder / "metrics.csv").read_text().splitlines()
        atomic_write_text(target_folder / "metrics.csv", "\n".join(join_launches(metrics)) + "\n")
        if folder != source:
            last = checkpoints(folder)[-1][1]
            slim_checkpoint(last, target_folder / last.name)
    if staged and (source / STAGES).is_file():
        shutil.copy2(source / STAGES, staging / STAGES)
    for path in kept or [checkpoints(source)[-1][1]]:
        slim_checkpoint(path, staging / path.name)
    atomic_write_text(staging / "wall.json", json.dumps({"launches_seconds": seconds}) + "\n")
    shutil.rmtree(target, ignore_errors=True)
    staging.rename(target)
    return target
