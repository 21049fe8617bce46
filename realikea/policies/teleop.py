"""Keyboard teleoperation in MuJoCo's interactive viewer, recorded as a demonstration.

`realikea eval policy=teleop policy.record=demos/x.npz [asset=... resistance=...]` opens one
OpenTask (the configuration the usual config picks first, seeded `env.seed`) in
`mujoco.viewer.launch_passive` and steps it at the task's 10 Hz in real time; every key press
adds one control step's worth of command (hold a key: the keyboard's auto-repeat moves the TCP
continuously, clipped at the task's full speed of one unit per step). Translation is in world
axes as seen from behind the robot, looking at the cabinet:

    Up / Down arrow      towards / away from the cabinet  (a1 -/+ : world -x / +x)
    Left / Right arrow   left / right                     (a2 -/+ : world -y / +y)
    Page Up / Page Down  up / down                        (a3 +/- : world +z / -z)
    Home / End           pitch + / pitch -                (a0 +/-)
    Enter                toggle the gripper (starts open)  (a4 +1 open, -1 closed)
    Insert               end the episode now (kept as incomplete) and start the next one

Leave the viewer's own Space (pause) and Backspace (reset) alone. Closing the window (or
`episodes` finished episodes) ends the session; the demonstration is rewritten atomically after
every episode and at the end (realikea/policies/demonstration.py).

The key map and the action mapping are pure functions (`press`, `next_action`) so they are
tested without a display.
"""

from __future__ import annotations

import os
import sys
import threading
import time
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from omegaconf import DictConfig

from realikea.assets.library import training_configurations
from realikea.errors import RealIkeaError
from realikea.files import repo_path
from realikea.policies.demonstration import Recorder, Session
from realikea.tasks.open_task import ACTION_SIZE, OpenTask

# GLFW key codes, as mujoco.viewer's key_callback receives them
KEY_ENTER, KEY_INSERT = 257, 260
KEY_RIGHT, KEY_LEFT, KEY_DOWN, KEY_UP = 262, 263, 264, 265
KEY_PAGE_UP, KEY_PAGE_DOWN, KEY_HOME, KEY_END = 266, 267, 268, 269
KEY_KP_ENTER = 335

OPEN, CLOSED = 1.0, -1.0
# key -> (action index, sign) for the motion keys
MOTION_KEYS = {
    KEY_UP: (1, -1.0),
    KEY_DOWN: (1, +1.0),
    KEY_LEFT: (2, -1.0),
    KEY_RIGHT: (2, +1.0),
    KEY_PAGE_UP: (3, +1.0),
    KEY_PAGE_DOWN: (3, -1.0),
    KEY_HOME: (0, +1.0),
    KEY_END: (0, -1.0),
}
GRIPPER_KEYS = (KEY_ENTER, KEY_KP_ENTER)
RESET_KEYS = (KEY_INSERT,)

KEY_HELP = """\
teleop keys (world axes seen from behind the robot; one press = one control step, hold to move):
  Up / Down arrow       towards / away from the cabinet   (a1 -/+, world -x/+x)
  Left / Right arrow    left / right                      (a2 -/+, world -y/+y)
  Page Up / Page Down   up / down                         (a3 +/-, world +z/-z)
  Home / End            pitch + / pitch -                 (a0 +/-)
  Enter                 toggle the gripper (starts open)  (a4 +1/-1)
  Insert                end this episode now (kept, marked incomplete), start the next
  close the window      end the session (leave the viewer's Space and Backspace alone)"""


@dataclass(frozen=True)
class TeleopState:
    """Commands collected since the last control step, the gripper and a pending reset."""

    pending: tuple[float, ...] = (0.0,) * (ACTION_SIZE - 1)  # a0..a3
    gripper: float = OPEN
    reset: bool = False
    presses: int = field(default=0, compare=False)


def press(state: TeleopState, key: int) -> TeleopState:
    """The state after one key press (or auto-repeat); unknown keys change nothing."""
    if key in MOTION_KEYS:
        index, sign = MOTION_KEYS[key]
        pending = list(state.pending)
        pending[index] += sign
        return replace(state, pending=tuple(pending), presses=state.presses + 1)
    if key in GRIPPER_KEYS:
        return replace(state, gripper=CLOSED if state.gripper == OPEN else OPEN)
    if key in RESET_KEYS:
        return replace(state, reset=True)
    return state


def next_action(state: TeleopState) -> tuple[np.ndarray, bool, TeleopState]:
    """The 5-D action of the next control step, whether to end the episode, the state after.

    Presses since the last step add up and are clipped to the task's range [-1, 1] (a held key
    auto-repeats faster than 10 Hz: full speed); they are used up, the gripper command stays.
    """
    action = np.zeros(ACTION_SIZE)
    action[: ACTION_SIZE - 1] = np.clip(state.pending, -1.0, 1.0)
    action[ACTION_SIZE - 1] = state.gripper
    return action, state.reset, TeleopState(gripper=state.gripper)


class Keyboard:
    """The viewer thread's key presses, collected for the control loop (thread safe)."""

    def __init__(self):
        self._lock = threading.Lock()
        self._state = TeleopState()

    def on_key(self, key: int) -> None:
        with self._lock:
            self._state = press(self._state, int(key))

    def take(self) -> tuple[np.ndarray, bool]:
        with self._lock:
            action, reset, self._state = next_action(self._state)
        return action, reset


def require_display() -> None:
    """A clear RealIkeaError when MuJoCo's interactive viewer cannot open a window here."""
    hint = "record on a desktop (or ssh -X); replay demonstrations headless with policy=replay"
    if sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        raise RealIkeaError(
            f"policy=teleop needs a display for MuJoCo's viewer: neither DISPLAY nor "
            f"WAYLAND_DISPLAY is set ({hint})"
        )
    if sys.platform == "darwin" and "mjpython" not in Path(sys.executable).name:
        raise RealIkeaError("policy=teleop on macOS must run under `mjpython -m realikea.cli`")
    try:
        import glfw
    except Exception as err:
        raise RealIkeaError(f"policy=teleop needs GLFW for MuJoCo's viewer ({err})") from err
    if sys.platform != "darwin":  # a DISPLAY that is set but unreachable
        with warnings.catch_warnings():  # pyGLFW also warns; the error below says it better
            warnings.simplefilter("ignore")
            ok = glfw.init()
        if not ok:
            raise RealIkeaError(
                f"policy=teleop cannot open a window: GLFW failed to start ({hint})"
            )
        glfw.terminate()


class TeleopPolicy:
    """Actions from the keyboard; `run_interactive` is the session `realikea eval` runs."""

    name = "teleop"

    def __init__(self, record: Path | None, realtime: bool = True):
        self.record = record
        self.realtime = realtime
        self.keyboard = Keyboard()
        self._saved = 0

    @classmethod
    def from_config(cls, cfg: DictConfig) -> TeleopPolicy:
        record = cfg.policy.get("record")
        return cls(repo_path(record) if record else None, bool(cfg.policy.get("realtime", True)))

    def reset(self, env_ids, facts) -> None:
        """Nothing to plan: the operator is the policy."""

    def act(self, obs: np.ndarray) -> np.ndarray:
        """The keyboard's command for every env (meaningful with the viewer running)."""
        action, _ = self.keyboard.take()
        return np.tile(action, (len(obs), 1))

    def run_interactive(self, cfg: DictConfig, overrides: list[str]) -> int:
        """One task in the viewer at 10 Hz real time until the window closes; records episodes."""
        require_display()
        import mujoco.viewer

        seed = int(cfg.env.seed)
        (mjcf,) = training_configurations(cfg, 1, seed)
        task = OpenTask(cfg, mjcf, seed)
        recorder = Recorder(task, cfg, mjcf, seed, overrides, source="teleop")
        session = Session(task, recorder)
        episodes = int(cfg.episodes)
        period = task.decimation * task.model.opt.timestep
        print(KEY_HELP)
        print(
            f"configuration {task.config_id} ({task.joint_type}), seed {seed}; "
            f"recording to {self.record or 'nowhere (set policy.record=PATH.npz)'}"
        )
        try:
            viewer = mujoco.viewer.launch_passive(
                task.model, task.data, key_callback=self.keyboard.on_key
            )
        except Exception as err:
            raise RealIkeaError(f"policy=teleop: MuJoCo's viewer did not open ({err})") from err
        try:
            with viewer:
                tick = time.perf_counter()
                while viewer.is_running() and len(recorder.finished) < episodes:
                    action, cut = self.keyboard.take()
                    with viewer.lock():
                        ended = session.cut() if cut else session.step(action)[1]
                    viewer.sync()
                    if ended is not None:
                        self._report(len(recorder.finished), ended.summary)
                        self._save(recorder)
                    tick += period
                    if self.realtime:
                        time.sleep(max(tick - time.perf_counter(), 0.0))
                        tick = max(tick, time.perf_counter() - period)
        finally:
            session.finish()
            self._save(recorder)
        return 0

    @staticmethod
    def _report(number: int, summary: dict) -> None:
        label = summary.get("outcome", "incomplete") if summary.get("complete") else "incomplete"
        strategy = f", strategy {summary['strategy']}" if "strategy" in summary else ""
        print(
            f"episode {number}: {label} ({summary.get('termination')}, {summary['steps']} steps, "
            f"opening {summary.get('opening', float('nan')):.3f}{strategy})"
        )

    def _save(self, recorder) -> None:
        """Rewrite the demonstration when it has episodes it did not have at the last save."""
        if self.record is not None and len(recorder.finished) > self._saved:
            path = recorder.save(self.record)
            self._saved = len(recorder.finished)
            print(f"demonstration: {path} ({len(recorder.finished)} episodes)")
