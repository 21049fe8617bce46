"""One scene of the opening task: reset, the 5-D action through IK, physics, reward, termination.

A task knows exactly one scene (the robot in front of one configuration); vectorizing many of
them is the env pool's business (realikea/pool).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import mujoco
import numpy as np
from omegaconf import DictConfig, OmegaConf

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, Catalog, group_name
from realikea.assets.catch_geometry import LipCatch, catch_features_at
from realikea.errors import RealIkeaError
from realikea.rewards import StepValues, reward_from_config
from realikea.sim.ik import IKController, rolled_nominal, tcp_pitch
from realikea.sim.robot import FINGER_BODIES, HAND_BODY, PAD_GEOMS, PAD_THICKNESS, GripperModel
from realikea.sim.scene import (
    ARM_ACTUATORS,
    ARM_JOINTS,
    CABINET_ROOT,
    FINGER_JOINTS,
    FRONT_JOINT,
    GRIPPER_ACTUATOR,
    HANDLE_SITE,
    PART_BODY,
    TCP_SITE,
    build_scene,
    placement,
    reset_home,
    subtree_geoms,
)
from realikea.tasks import mirror, observations
from realikea.tasks.contacts import (
    SAMPLE_FORCES,
    SUMMARY_KEYS,
    ClassifierParams,
    ContactLog,
    ContactMonitor,
    sample_forces,
)
from realikea.tasks.contract import StepResult
from realikea.tasks.facts import SceneFacts
from realikea.tasks.failure_modes import FAILURE_KEYS, FailureLog, FailureMonitor, FailureParams
from realikea.tasks.grip import NO_GRIP, GripSensor
from realikea.tasks.outcome import outcome
from realikea.tasks.randomization import PosePerturbation, Randomization
from realikea.tasks.start_state import AjarStart, PregraspStart
from realikea.tasks.terminations import TIMEOUT, Terminations, termination

ACTION_SIZE = 5
# The Panda reflected in the vertical plane through its base: joints 1, 3, 5 and 7 turn the other
# way (their limits are symmetric about 0), 2, 4 and 6 keep their angles; with the hand mounted at
# -45 deg on the flange, the reflected hand is the rolled hand turned a half turn (the same jaws)
MIRRORED_JOINTS = np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
# MuJoCo's warnings that a step went wrong: a NaN/huge state or control (MuJoCo then silently
# resets the state or zeroes the control) or a full arena (contacts or constraints dropped)
INSTABILITY_WARNINGS = tuple(
    int(getattr(mujoco.mjtWarning, name))
    for name in (
        "mjWARN_BADQPOS", "mjWARN_BADQVEL", "mjWARN_BADQACC", "mjWARN_BADCTRL",
        "mjWARN_CONTACTFULL", "mjWARN_CNSTRFULL",
    )
)  # fmt: skip


@dataclass
class EpisodeState:
    """What the task remembers within an episode."""

    stage: int = 1
    steps: int = 0
    grasped: bool = False  # the stage has been 4 at some step of the episode
    progress: float = 0.0  # opening / success threshold after the last step (or the reset)
    prev_action: np.ndarray = field(default_factory=lambda: np.zeros(ACTION_SIZE))
    prev_prev_action: np.ndarray = field(default_factory=lambda: np.zeros(ACTION_SIZE))
    ik_failures: int = 0
    stagnant: int = 0
    at_pregrasp: bool = False  # started at the pre-grasp pose (a start-state curriculum)
    ajar: bool = False  # started with the front ajar (a start-state curriculum)
    term_sums: dict[str, float] = field(default_factory=dict)  # reward term -> episode sum
    contacts: ContactLog = field(default_factory=ContactLog)
    failure: FailureLog = field(default_factory=FailureLog)


class OpenTask:
    """The robot opening one configuration's front (drawer, door or flap): a `Task`
    (`realikea/tasks/contract.py`)."""

    observation_size = observations.SIZE
    action_size = ACTION_SIZE
    # what an episode's record in the env pool keeps of the final info
    episode_keys = (
        "outcome", "termination", "opening", "stage", "reward_terms", "category", "kind",
        "pregrasp", "ajar", "pad_enters",
        *SUMMARY_KEYS,
        *FAILURE_KEYS,
    )  # fmt: skip

    def __init__(self, cfg: DictConfig, config_mjcf: Path, seed: int = 0):
        task = cfg.task
        self.cfg = cfg
        if not Path(config_mjcf).is_file():  # before its folder is read as a configuration id
            raise RealIkeaError(f"MJCF not found: {config_mjcf}")
        self.config_id = Path(config_mjcf).parent.name
        self.part, self.base = _catalog_entries(self.config_id)
        _check_placements(cfg)
        place = placement(cfg, self.part.category, self.base.kind)
        self.model = build_scene(Path(config_mjcf), cfg, place)
        self.data = mujoco.MjData(self.model)
        self._place_robot(cfg, place)
        self.gripper = GripperModel.from_config(cfg.gripper)
        self.reward, self.params = reward_from_config(OmegaConf.to_container(task.reward))
        self.randomization = Randomization.from_config(cfg.dr)
        self.start = PregraspStart.from_config(task)
        self.ajar = AjarStart.from_config(task)
        self.rng = np.random.default_rng(seed)
        self._read_task(task)
        self.iteration = 0
        parts, panel = self._index_model(task)
        self.perturb = PosePerturbation(self.model, self._part, self.model.body(CABINET_ROOT).id)
        self.grip_sensor = GripSensor(self.model, PAD_GEOMS, FINGER_BODIES, PART_BODY)
        self.state = EpisodeState()
        self.grip = NO_GRIP  # the jaws and the handle as the last step's reward read them
        self._nominal_handle = np.zeros(3)
        self._t1, self._t2 = self.o1, self.o2
        self._mesh = str(Path(config_mjcf).parent / "meshes" / "visual.obj")
        self.pad_enters = pad_enters(self._mesh, self.part.category)
        self._monitor_contacts(cfg, parts, panel)
        self._step_forces, self._step_samples = np.zeros(len(SAMPLE_FORCES)), 0
        self._excess = 0.0  # the last action's squared excess beyond the clip to [-1, 1]

    def _place_robot(self, cfg: DictConfig, place) -> None:
        """The hand's nominal orientation, the home posture (turned with the hand's roll) and
        the IK controller, for the robot where the scene placed it."""
        roll = _hand_roll(self.model, self.base.mount_roll_deg, place.hand_turned)
        mirrored_arm = _mirrored_door(self.model, roll)
        # the policy sees and drives a mirrored door as its twin (`realikea/tasks/mirror.py`)
        self.mirrored = bool(cfg.task.get("mirror_doors")) and mirrored_arm
        self.nominal = rolled_nominal(roll)
        self.home = place.home
        base = self.model.body("link0").pos.copy()  # where the scene placed the robot
        if roll:  # turning the hand about its approach axis is turning joint 7
            start, posture = self.home - [0, 0, 0, 0, 0, 0, roll], None
            if mirrored_arm:  # the right-hinged twin's arm, mirrored
                start = posture = MIRRORED_JOINTS * self.home
            rolled = IKController.from_config(
                cfg, nominal=self.nominal, home=posture, base_pos=base
            )
            position, _ = rolled.tcp_pose(start)
            self.home = rolled.converge(start, position, 0.0)
        self.ik = IKController.from_config(cfg, nominal=self.nominal, home=self.home, base_pos=base)

    def _read_task(self, task: DictConfig) -> None:
        """The task's constants as plain numbers: OmegaConf lookups cost tens of microseconds
        each on the hot path."""
        self.decimation = int(task.decimation)
        self.horizon = round(
            float(task.episode_seconds) / (self.decimation * self.model.opt.timestep)
        )
        self.pitch_scale = float(task.action.pitch_scale)
        self.translation_scale = float(task.action.translation_scale)
        self.o1, self.o2 = (np.asarray(task.targets[k], float) for k in ("o1", "o2"))
        self.lateral_bias = float(task.targets.get("lateral_bias", 0.0))
        ws = task.workspace
        self.workspace = (np.asarray(ws.below, float), np.asarray(ws.above, float))
        self.pitch_range = (float(ws.pitch[0]), float(ws.pitch[1]))
        self.terminations = Terminations(**task.terminations)
        self.outcome_thresholds = OmegaConf.to_container(task.outcome)

    def _index_model(self, task: DictConfig) -> tuple[list[int], list[int]]:
        """The model's ids the steps read (joints, actuators, sites, bodies) and the front's
        joint; the part's geoms and the rest of the moving front's (the panel)."""
        m = self.model
        self._arm_q = np.array([m.jnt_qposadr[m.joint(j).id] for j in ARM_JOINTS])
        self._finger_q = np.array([m.jnt_qposadr[m.joint(j).id] for j in FINGER_JOINTS])
        self._arm_act = np.array([m.actuator(a).id for a in ARM_ACTUATORS])
        self._grip_act = m.actuator(GRIPPER_ACTUATOR).id
        front = m.joint(FRONT_JOINT)
        self.joint_type = "slide" if front.type[0] == mujoco.mjtJoint.mjJNT_SLIDE else "hinge"
        self._front, self._front_q, self._front_v = (
            front.id,
            m.jnt_qposadr[front.id],
            m.jnt_dofadr[front.id],
        )
        self._success = float(task.outcome.success[self.joint_type])
        # the front rests on its closed stop below this (the middle of its range)
        self._closed_side = float(m.jnt_range[front.id].mean())
        self._category = CATEGORIES.index(self.part.category)
        self._jac = np.zeros((3, m.nv))
        self._tcp, self._handle = m.site(TCP_SITE).id, m.site(HANDLE_SITE).id
        self._base = m.body("link0").id
        self._part = m.body(PART_BODY).id
        parts = np.flatnonzero(m.geom_bodyid == self._part).tolist()
        panel = [g for g in subtree_geoms(m, m.jnt_bodyid[front.id]) if g not in parts]
        return parts, panel

    def _monitor_contacts(self, cfg: DictConfig, parts: list[int], panel: list[int]) -> None:
        """The strategy classifier and the failure modes, when evaluation's `contacts` settings
        (realikea/conf/eval.yaml) log them."""
        m = self.model
        contacts = cfg.get("contacts")
        self.classifier = self.contact_monitor = self.failure_monitor = None
        if contacts is not None and bool(contacts.log):
            settings = OmegaConf.to_container(contacts)
            self.failure_params = FailureParams(**settings.pop("failure"))
            self.classifier = ClassifierParams(**{k: v for k, v in settings.items() if k != "log"})
            gripper_bodies = [m.body(b).id for b in (HAND_BODY, *FINGER_BODIES)]
            self.contact_monitor = ContactMonitor(m, gripper_bodies, parts, panel)
            robot = subtree_geoms(m, self._base)
            self.failure_monitor = FailureMonitor(m, robot, parts + panel)

    # --- reading the scene ----------------------------------------------------------------
    @property
    def opening(self) -> float:
        return float(self.data.qpos[self._front_q])

    @property
    def aperture(self) -> float:
        left, right = self._finger_q  # numpy's sum of the two, in floats (0.0 + as its reduction)
        qpos = self.data.qpos
        return (0.0 + qpos.item(left) + qpos.item(right)) / (2 * self.gripper.stroke)

    def _targets(self) -> tuple[float, float]:
        """Distances of the TCP to the targets t1, t2 (np.linalg.norm's arithmetic, in floats)."""
        rel = self.data.site_xpos[self._tcp] - self.data.site_xpos[self._handle]
        e1, e2 = rel - self._t1, rel - self._t2
        return math.sqrt(e1.dot(e1)), math.sqrt(e2.dot(e2))

    def _step_values(self, stage: int, action: list[float], ik_ok: bool) -> StepValues:
        """What the reward reads of the scene now, the stage still `stage`."""
        s, d = self.state, self.data
        d1, d2 = self._targets()
        opening = self.opening
        p, grip, push = self.params, NO_GRIP, 0.0
        if self.reward.reads_grip:
            velocity = self._handle_jacobian()
            lever = float(np.linalg.norm(velocity))
            site, u = d.site_xpos[self._handle].tolist(), (velocity / lever).tolist()
            grip = self.grip_sensor.read(d, site, u, p.straddle_radius, p.hook_cos)
            if p.w_push:  # read only where it is weighed (off in the default recipe)
                push = self._closed_stop_force() / lever
        self.grip = grip  # what the stage read: for traces (experiments/generalist/trace.py)
        return StepValues(
            stage, d1, d2, self.aperture, opening, opening / self._success, grip.straddle,
            grip.engaged, action, s.prev_action.tolist(), s.prev_prev_action.tolist(), ik_ok,
            grip.offset, push, excess=self._excess, prev_progress=s.progress,
        )  # fmt: skip

    def _handle_jacobian(self) -> np.ndarray:
        """The handle's world velocity per unit of the front's joint velocity (its norm: 1 for a
        drawer, the lever arm in m for a hinge)."""
        mujoco.mj_jacSite(self.model, self.data, self._jac, None, self._handle)
        return self._jac[:, self._front_v]

    def pull_direction(self) -> np.ndarray:
        """Unit world direction the handle moves in as the front opens (the joint's Jacobian)."""
        u = self._handle_jacobian()
        return u / np.linalg.norm(u)

    def pressing_force(self) -> float:
        """N at the handle with which the robot presses the closed front shut, after the last
        physics step: the force of the front's closed stop (a hinge's torque over the lever
        arm); 0 off the stop."""
        force = self._closed_stop_force()
        return force / float(np.linalg.norm(self._handle_jacobian())) if force else 0.0

    def _closed_stop_force(self) -> float:
        """The generalized force (N or N m) the front's closed stop holds; 0 off the stop."""
        d = self.data
        if d.qpos.item(self._front_q) > self._closed_side or not d.nefc:
            return 0.0
        rows = (d.efc_type == mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT) & (d.efc_id == self._front)
        return float(d.efc_force[rows].sum())

    def facts(self) -> SceneFacts:
        """The scene of the current episode for scripted policies (privileged, world frame)."""
        m, d = self.model, self.data
        anchor = axis = None
        if self.joint_type == "hinge":
            front = m.joint(FRONT_JOINT).id
            anchor, axis = d.xanchor[front].copy(), d.xaxis[front].copy()
        return SceneFacts(
            config_id=self.config_id,
            part_id=self.part.id,
            category=self.part.category,
            base_kind=self.base.kind,
            joint_type=self.joint_type,
            robot_base=d.xpos[self._base].copy(),
            handle_pos=d.site_xpos[self._handle].copy(),
            part_pos=d.xpos[self._part].copy(),
            part_rot=d.xmat[self._part].reshape(3, 3).copy(),
            pull_dir=self.pull_direction(),
            hinge_anchor=anchor,
            hinge_axis=axis,
            visual_mesh=self._mesh,
            tcp_nominal=self.nominal,
            pad_friction=self.gripper.pad_friction,
            max_aperture=2 * self.gripper.stroke,
        )

    def observe(self) -> np.ndarray:
        """The observation (`realikea/tasks/observations.py`), a mirrored door's reflected."""
        d = self.data
        aperture, opening = self.aperture, self.opening
        obs = observations.observation(
            observations.ObservationInputs(
                d.site_xpos[self._tcp].tolist(),
                d.site_xmat[self._tcp].reshape(3, 3).tolist(),
                d.site_xpos[self._handle].tolist(),
                d.xpos[self._base].tolist(),
                opening,
                float(d.qvel[self._front_v]),
                aperture,
                aperture < self.params.close_below,
                self.state.prev_action.tolist(),
                self.state.stage,
                self.joint_type == "hinge",
                d.xaxis[self._front].tolist(),
                self.pull_direction().tolist(),
                opening / self._success,
                self._category,
            )
        )
        return self.reflected(obs, mirror.OBSERVATION_SIGNS)

    def reflected(self, values: np.ndarray, signs: np.ndarray) -> np.ndarray:
        """An observation or action (`signs`: `mirror`'s for it) carried between the world's
        frame and the policy's, either way: reflected on a mirrored door (the reflection is its
        own inverse), unchanged on any other."""
        return values * signs if self.mirrored else values

    # --- episode --------------------------------------------------------------------------
    def reset(self) -> np.ndarray:
        """Start an episode (poses perturbed when randomization is active)."""
        active = self.randomization.active(self.iteration)
        self.perturb.apply(self.rng if active else None, self.randomization)
        reset_home(self.model, self.data, self.cfg, self.home)
        self.state = EpisodeState()
        self._excess = 0.0
        self._nominal_handle = self.data.site_xpos[self._handle].copy()
        # the paper's approach offsets share one lateral bias, along the handle's long axis
        lateral = self.lateral_bias * self.data.xmat[self._part].reshape(3, 3)[:, 0]
        self._t1, self._t2 = self.o1 + lateral, self.o2 + lateral
        group = group_name(self.part.category, self.base.kind)
        if self.start.draws(group, self.rng):
            self._start_at_pregrasp()
        elif (fraction := self.ajar.opening(group, self.rng)) is not None:
            self._start_ajar(fraction)
        values = self._step_values(1, [0.0] * ACTION_SIZE, True)
        self.state.stage = self.reward.next_stage(1, values, self.params)
        self.state.progress = values.progress
        return self.observe()

    def _start_at_pregrasp(self) -> None:
        """Put the arm at the pre-grasp pose (`realikea/tasks/start_state.py`): the TCP at the
        first approach target at the nominal pitch, the gripper open, the front closed. Where IK
        cannot reach it the episode starts at home."""
        try:
            posture = self.ik.converge(self.home, self._nominal_handle + self._t1, 0.0)
        except RealIkeaError:
            return
        reset_home(self.model, self.data, self.cfg, posture)
        self.state.at_pregrasp = True

    def _start_ajar(self, fraction: float) -> None:
        """Open the front to `fraction` of the success mark, at rest, the hand at home
        (`realikea/tasks/start_state.py`). The episode counts as grasped: the reward pays the
        opening from the first step, as after a hook that pulled this far and came off."""
        self.data.qpos[self._front_q] = fraction * self._success
        mujoco.mj_forward(self.model, self.data)
        self.state.ajar = self.state.grasped = True

    def apply_action(self, action) -> bool:
        """Turn the 5-D action into actuator targets through IK; returns whether IK succeeded.
        A mirrored door's action is reflected first (`realikea/tasks/mirror.py`)."""
        action = np.asarray(action, dtype=np.float64)
        if action.shape != (ACTION_SIZE,) or not np.isfinite(action).all():
            raise RealIkeaError(f"action must be 5 finite numbers, got {action!r}")
        action = self.reflected(action, mirror.ACTION_SIGNS)
        # np.clip's values without its per-call overhead (the hot path runs once per env-step)
        a = np.minimum(np.maximum(action, -1.0), 1.0)
        d = self.data
        below, above = self.workspace
        tcp = d.site_xpos[self._tcp]
        target = tcp + self.translation_scale * a[1:4]
        handle = self._nominal_handle
        target = np.minimum(np.maximum(target, handle + below), handle + above)
        pitch = (
            tcp_pitch(d.site_xmat[self._tcp].reshape(3, 3), self.nominal) + self.pitch_scale * a[0]
        )
        pitch = min(max(pitch, self.pitch_range[0]), self.pitch_range[1])
        result = self.ik.solve(d.qpos[self._arm_q], target, pitch)
        d.ctrl[self._arm_act] = result.q
        d.ctrl[self._grip_act] = self.gripper.ctrl(a[4])
        self._last_action, self._tcp_before = a, tcp.copy()
        self._excess = sum(max(abs(x) - 1.0, 0.0) ** 2 for x in action.tolist())
        return result.ok

    def simulate(self) -> None:
        """Advance the physics by one control period."""
        if self.contact_monitor is None:
            mujoco.mj_step(self.model, self.data, nstep=self.decimation)
            return
        every = self.classifier.sample_substeps  # same physics, sampled between substeps
        self._step_forces[:], self._step_samples = 0.0, 0
        for _ in range(self.decimation // every):
            mujoco.mj_step(self.model, self.data, nstep=every)
            self._sample_contacts()
        if self.decimation % every:
            mujoco.mj_step(self.model, self.data, nstep=self.decimation % every)

    def _sample_contacts(self) -> None:
        """One sample of the strategy classifier's and the failure modes' evidence."""
        d = self.data
        contacts = self.contact_monitor.forces(d)
        u = self.pull_direction() if contacts else None
        rate = float(d.qvel[self._front_v])
        self.contact_monitor.record(self.state.contacts, contacts, u, rate, self.classifier)
        self._step_forces += sample_forces(contacts, u)
        self._step_samples += 1
        reach = float(np.linalg.norm(d.site_xpos[self._tcp] - d.site_xpos[self._handle]))
        pitch = tcp_pitch(d.site_xmat[self._tcp].reshape(3, 3), self.nominal)
        self.failure_monitor.record(
            self.state.failure, d, contacts, u, reach, pitch, self.failure_params
        )

    def diverged(self) -> bool:
        """NaN state or MuJoCo's own instability warning."""
        number = self.data.warning.number.tolist()
        bad = any(number[w] > 0 for w in INSTABILITY_WARNINGS)
        return bool(bad or not np.isfinite(self.data.qpos).all())

    def evaluate(self, ik_ok: bool) -> StepResult:
        """Reward (the weighted `REWARD_TERMS`), terminations (`TERMINATIONS`) and info after the
        physics of a control step; an episode's end carries each term's sum in `reward_terms`.
        With the contact monitor on, every step's info carries `contact_forces`: the mean over
        the step's samples of `contacts.SAMPLE_FORCES` (N)."""
        s, p, a = self.state, self.params, self._last_action
        s.steps += 1
        diverged = self.diverged()
        values = self._step_values(s.stage, a.tolist(), ik_ok)
        s.stage = self.reward.next_stage(s.stage, values, p)
        s.grasped = s.grasped or s.stage == 4
        values = replace(values, stage=s.stage, grasped=s.grasped)
        opening = values.opening
        reward = 0.0
        for name, value in self.reward.weighted_terms(values, p):
            reward += value
            if not diverged:
                s.term_sums[name] = s.term_sums.get(name, 0.0) + value
        s.ik_failures = 0 if ik_ok else s.ik_failures + 1
        term = self.terminations
        step = self.data.site_xpos[self._tcp] - self._tcp_before
        moved = math.sqrt(step.dot(step))  # np.linalg.norm's arithmetic
        command = a[1:4]
        commanded = math.sqrt(command.dot(command)) > term.stagnation_command
        s.stagnant = s.stagnant + 1 if commanded and moved < term.stagnation_motion else 0
        s.prev_prev_action, s.prev_action = s.prev_action, a
        s.progress = values.progress
        if diverged:
            reward = 0.0
        ended = termination(s, term, diverged)
        terminated = ended is not None
        truncated = not terminated and s.steps >= self.horizon
        info = {"opening": opening, "stage": s.stage, "ik_ok": ik_ok, "diverged": diverged}
        if self.contact_monitor is not None:
            info["contact_forces"] = (self._step_forces / max(self._step_samples, 1)).tolist()
        if terminated or truncated:
            info["outcome"] = str(outcome(opening, self.joint_type, self.outcome_thresholds))
            info["termination"] = ended or TIMEOUT
            info["reward_terms"] = dict(s.term_sums)
            info["category"], info["kind"] = self.part.category, self.base.kind
            info["pad_enters"] = self.pad_enters
            if s.at_pregrasp:
                info["pregrasp"] = True
            if s.ajar:
                info["ajar"] = True
            if self.contact_monitor is not None:
                period = self.classifier.sample_substeps * self.model.opt.timestep
                info.update(s.contacts.summary(self.part.category, self.classifier, period))
                info.update(
                    s.failure.summary(
                        info["outcome"], self.part.category, self.failure_params, period
                    )
                )
        obs = self.observe() if not diverged else np.zeros(observations.SIZE)
        return StepResult(obs, reward, terminated, truncated, info)

    def step(self, action) -> StepResult:
        """apply_action, simulate, evaluate: one control step."""
        ok = self.apply_action(action)
        self.simulate()
        return self.evaluate(ok)


def pad_enters(mesh: str, category: str) -> bool:
    """Whether the fingertip pad (`PAD_THICKNESS`: 9 mm) fits behind the part's catch: on a
    finger pull, a channel behind the lip at least that wide (`LipCatch.channel`); the other
    categories' catches are not measured, and count as fitting."""
    if category != "finger_pull":
        return True
    found = catch_features_at(mesh, category)
    return isinstance(found, LipCatch) and found.channel >= PAD_THICKNESS


def _hand_roll(model: mujoco.MjModel, mount_roll_deg: float, turned: bool = False) -> float:
    """The hand's roll (rad) about its approach axis in a configuration, fixed so the jaws close
    across the handle (vertical on doors). The hand is symmetric under a half turn, so of the
    two rolls that do, a hinged front gets the one whose opening turns the wrist in the positive
    pitch direction, where the Panda's wrist has its range (about +1.5 rad against -0.7 rad for
    the rolled hand at handle height, `python experiments/reach/reach.py`); `turned` takes the
    other one (a placement's `hand_turned`: a finger pull's wedge on a door tips the hand the
    negative way, which leaves joint 6 0.07-0.09 rad from its limit at the catch:
    experiments/kitchen/results/wrist_load.md)."""
    roll = math.radians(mount_roll_deg % 180.0)
    joint = model.joint(FRONT_JOINT)
    if joint.type[0] == mujoco.mjtJoint.mjJNT_HINGE:
        axis = model.jnt_axis[joint.id]  # the front's frame is the world's, turned by no more
        if float(axis @ rolled_nominal(roll)[:, 0]) < 0:  # than the pose randomization's degrees
            roll -= math.pi
    if turned:
        roll += math.pi if roll <= 0 else -math.pi
    return roll


def _mirrored_door(model: mujoco.MjModel, roll: float) -> bool:
    """Whether a configuration is a door whose hand `_hand_roll` turned the other way (the
    left-hinged doors: the handle swings towards -y), whose arm starts from the mirror image of
    the home posture (`MIRRORED_JOINTS`). The home posture is not mirror-symmetric (wrist bent
    to one side, joint 5 at +1.51 rad, the TCP 0.15 m to one side of the base): with it, the pull
    on a wide left-hinged door runs joints 5 and 6 into their upper limits at about 0.7 rad,
    where its right-hinged twin keeps 0.5 rad on both; mirrored, the two pulls mirror each
    other."""
    joint = model.joint(FRONT_JOINT)
    vertical = abs(float(model.jnt_axis[joint.id][2])) > 0.5
    return joint.type[0] == mujoco.mjtJoint.mjJNT_HINGE and vertical and roll < 0


def _check_placements(cfg: DictConfig) -> None:
    """Every kitchen placement names a part category and a base kind the catalog has (one that
    names neither would never apply)."""
    robot = cfg.scene.get("robot")
    for i, entry in enumerate((robot.get("placements") if robot else None) or []):
        if entry.get("category") not in CATEGORIES or entry.get("kind") not in BASE_KINDS:
            raise RealIkeaError(
                f"scene.robot.placements[{i}] names category {entry.get('category')!r} and kind "
                f"{entry.get('kind')!r}: categories {', '.join(CATEGORIES)}; kinds "
                f"{', '.join(BASE_KINDS)}"
            )


def _catalog_entries(config_id: str):
    """The catalog's part and base of a configuration id `<part>__<base>`."""
    part_id, sep, base_id = config_id.partition("__")
    if not sep:
        raise RealIkeaError(f"{config_id!r} is not a configuration id of the form <part>__<base>")
    catalog = Catalog.load()
    return catalog.part(part_id), catalog.base(base_id)
