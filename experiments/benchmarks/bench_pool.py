"""Speed of the env pool against the physics limit and gymnasium's AsyncVectorEnv.

    python experiments/benchmarks/bench_pool.py     # writes experiments/benchmarks/bench_pool.md

For each number of envs (configurations of two-point handles on every base, drawn as training
draws them, CoACD collision, fixed poses) the same work is done three ways, back to back:

1. a recording pass (in-process, not timed) steps the envs with a scripted approach-grasp-pull
   policy plus noise, so that the contact phases of a learned policy are in the workload; it
   records the actions, the actuator controls the IK produced and the physics state and solver
   warm start every `--chunk` control steps;
2. the pool (one worker per core) replays the recorded actions: its trajectories are those of
   the recording (the pool is deterministic and equal to single tasks, tests/test_pool.py);
3. the physics limit: the same models advanced by the same number of physics steps with
   `mujoco.rollout` (recorded controls, from the recorded states, with `initial_warmstart`,
   `--chunk` x decimation physics steps per call, one Python thread per core: the GIL is
   released during each call). Different configurations have different model sizes, and one
   rollout call needs models of one size signature and MjData per thread, so each call rolls out
   one env. The replay check compares the rollout's end state with the recorded one;
4. gymnasium's AsyncVectorEnv (one spawned subprocess per env, same-step auto-reset) over
   `realikea.pool.gym_env.OpenTaskEnv`, replaying the same actions.

Then: where the time goes (CPU per part of a control step, measured in-process on the same
actions with an instrumented task, `ProfiledTask`; the workers' CPU share and the main process's
wait, read from /proc around the pool's timed window),
a design check at 8 envs (pool vs in-process serial vs physics threaded through
`mujoco.rollout` with IK/reward serial in Python), and the CoACD vs hull cost per physics step
on the same configurations (each source's own closed-loop run, physics timed single-threaded).
"""

from __future__ import annotations

import argparse
import importlib.metadata
import json
import os
import platform
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from functools import partial
from pathlib import Path
from typing import NamedTuple

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")  # every worker and subprocess single-threaded, alike

import gymnasium as gym  # noqa: E402
import mujoco  # noqa: E402
import mujoco.rollout  # noqa: E402
import numpy as np  # noqa: E402
from omegaconf import OmegaConf  # noqa: E402

from realikea.assets.library import training_configurations  # noqa: E402
from realikea.config import load_config  # noqa: E402
from realikea.files import atomic_write_text  # noqa: E402
from realikea.pool.env_pool import EnvPool, available_cores  # noqa: E402
from realikea.pool.gym_env import OpenTaskEnv  # noqa: E402
from realikea.sources import SOURCES, model_name  # noqa: E402
from realikea.tasks import observations  # noqa: E402
from realikea.tasks.open_task import OpenTask  # noqa: E402

SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS
S = observations.slices()
OVERRIDES = ["asset=two_point", "dr=fixed"]


# --- workload ----------------------------------------------------------------------------------
def scripted(obs: np.ndarray, k: np.ndarray, rng: np.random.Generator, noise: float) -> np.ndarray:
    """Approach 6 cm in front of the handle, move onto it, close, pull; plus Gaussian noise."""
    rel = obs[:, S["handle_from_tcp"]].copy()
    goal = np.where((k < 30)[:, None], rel + np.array([0.06, 0.0, 0.0]), rel)
    goal[k >= 55] = (0.05, 0.0, 0.0)
    a = np.zeros((len(obs), 5))
    a[:, 1:4] = np.clip(goal / 0.01, -1.0, 1.0)
    a[:, 4] = np.where(k < 45, 1.0, -1.0)
    return np.clip(a + noise * rng.standard_normal(a.shape), -1.0, 1.0)


class Recording:
    """Actions, controls, chunk-start states and warm starts of an in-process run."""

    def __init__(self, cfg, paths, seed, steps, chunk, warmup, noise=0.3):
        n = len(paths)
        self.tasks = [OpenTask(cfg, p, seed + i) for i, p in enumerate(paths)]
        self.steps, self.chunk, self.decimation = steps, chunk, self.tasks[0].decimation
        nchunk = -(-steps // chunk)
        obs = np.array([t.reset() for t in self.tasks])
        k = np.zeros(n, np.int64)
        rng = np.random.default_rng(seed)
        self.actions = np.zeros((steps, n, 5))
        self.ctrl = [np.zeros((steps, t.model.nu)) for t in self.tasks]
        self.state = [np.zeros((nchunk, mujoco.mj_stateSize(t.model, SPEC))) for t in self.tasks]
        self.warm = [np.zeros((nchunk, t.model.nv)) for t in self.tasks]
        self.reset_in_chunk = np.zeros((n, nchunk), bool)
        contacts = 0
        for s in range(steps):
            a = scripted(obs, k, rng, noise)
            self.actions[s] = a
            for i, t in enumerate(self.tasks):
                if s % chunk == 0:
                    mujoco.mj_getState(t.model, t.data, self.state[i][s // chunk], SPEC)
                    self.warm[i][s // chunk] = t.data.qacc_warmstart
                ok = t.apply_action(a[i])
                self.ctrl[i][s] = t.data.ctrl
                t.simulate()
                contacts += t.data.ncon if s >= warmup else 0
                r = t.evaluate(ok)
                if r.terminated or r.truncated:
                    obs[i], k[i] = t.reset(), 0
                    self.reset_in_chunk[i, s // chunk] = True
                else:
                    obs[i], k[i] = r.obs, k[i] + 1
        self.mean_contacts = contacts / ((steps - warmup) * n)


# --- the three ways ------------------------------------------------------------------------------
def cpu_seconds(pid: int) -> float:
    """User + system CPU seconds of a process so far (/proc/<pid>/stat)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def run_pool(cfg, paths, seed, actions, warmup, workers=None):
    """Env-steps/s of the pool over actions[warmup:] (the first `warmup` steps untimed), its
    startup, and the timed window's wall seconds, steps and each worker's CPU seconds."""
    start = time.perf_counter()
    pool = EnvPool(cfg, paths, seed=seed, num_workers=workers)
    startup = time.perf_counter() - start
    try:
        for a in actions[:warmup]:
            pool.step(a)
        cpu0 = [cpu_seconds(pid) for pid in pool.worker_pids]
        start = time.perf_counter()
        for a in actions[warmup:]:
            pool.step(a)
        elapsed = time.perf_counter() - start
        cpu = [cpu_seconds(pid) - c for pid, c in zip(pool.worker_pids, cpu0, strict=True)]
        window = {"wall": elapsed, "steps": len(actions) - warmup, "worker_cpu": cpu}
        return actions[warmup:].size // 5 / elapsed, startup, window
    finally:
        pool.close()


PARTS = ("apply", "ik", "simulate", "evaluate", "observe", "reset")


class ProfiledTask(OpenTask):
    """The opening task with the thread CPU time of each part summed in `ProfiledTask.seconds`
    (in the process that steps it: the benchmark runs it in-process)."""

    seconds = dict.fromkeys(PARTS, 0.0)

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.ik.solve = self._timed("ik", self.ik.solve)

    @classmethod
    def _timed(cls, part, fn):
        def wrapper(*args, **kwargs):
            start = time.thread_time()
            try:
                return fn(*args, **kwargs)
            finally:
                cls.seconds[part] += time.thread_time() - start

        return wrapper

    def apply_action(self, action):
        return self._timed("apply", super().apply_action)(action)

    def simulate(self):
        return self._timed("simulate", super().simulate)()

    def evaluate(self, ik_ok):
        return self._timed("evaluate", super().evaluate)(ik_ok)

    def observe(self):
        return self._timed("observe", super().observe)()

    def reset(self):
        return self._timed("reset", super().reset)()


def profile_parts(cfg, paths, seed, actions, warmup) -> tuple[dict, float]:
    """CPU seconds per part over actions[warmup:] in-process, and the pool's whole step CPU."""
    with EnvPool(cfg, paths, seed=seed, num_workers=0, task_factory=ProfiledTask) as pool:
        for a in actions[:warmup]:
            pool.step(a)
        ProfiledTask.seconds = dict.fromkeys(PARTS, 0.0)
        start = time.thread_time()
        for a in actions[warmup:]:
            pool.step(a)
        busy = time.thread_time() - start
    return dict(ProfiledTask.seconds), busy


def physics_limit(rec: Recording, threads: int, warmup: int) -> tuple[float, float]:
    """Env-steps/s of the recorded physics after `warmup` control steps, replayed with
    mujoco.rollout on `threads` threads, and the largest deviation from the recorded states."""
    n, dec, chunk = len(rec.tasks), rec.decimation, rec.chunk
    datas = [mujoco.MjData(t.model) for t in rec.tasks]
    controls = [np.repeat(c, dec, axis=0) for c in rec.ctrl]
    out = [np.zeros((1, chunk * dec, len(s[0]))) for s in rec.state]
    deviation = np.zeros(n)

    def run(i):
        m, d = rec.tasks[i].model, datas[i]
        for c in range(warmup // chunk, len(rec.state[i])):
            lo, hi = c * chunk * dec, min((c + 1) * chunk, rec.steps) * dec
            state = out[i][:, : hi - lo]
            mujoco.rollout.rollout(
                m, d, rec.state[i][c : c + 1], controls[i][None, lo:hi],
                initial_warmstart=rec.warm[i][c : c + 1], state=state,
                sensordata=np.zeros((1, hi - lo, m.nsensordata)),
            )  # fmt: skip
            if c + 1 < len(rec.state[i]) and not rec.reset_in_chunk[i, c]:
                deviation[i] = max(deviation[i], np.abs(state[0, -1] - rec.state[i][c + 1]).max())

    start = time.perf_counter()
    with ThreadPoolExecutor(threads) as ex:
        list(ex.map(run, range(n)))
    elapsed = time.perf_counter() - start
    return n * (rec.steps - warmup // chunk * chunk) / elapsed, float(deviation.max())


def async_vector(cfg, paths, seed, actions, warmup) -> tuple[float, float]:
    container = OmegaConf.to_container(cfg, resolve=True)
    fns = [partial(OpenTaskEnv, container, str(p), seed + i) for i, p in enumerate(paths)]
    start = time.perf_counter()
    envs = gym.vector.AsyncVectorEnv(
        fns, context="spawn", autoreset_mode=gym.vector.AutoresetMode.SAME_STEP
    )
    try:
        envs.reset()
        startup = time.perf_counter() - start
        for a in actions[:warmup]:
            envs.step(a.astype(np.float32))
        start = time.perf_counter()
        for a in actions[warmup:]:
            envs.step(a.astype(np.float32))
        elapsed = time.perf_counter() - start
    finally:
        envs.close()
    return actions[warmup:].size // 5 / elapsed, startup


# --- design check --------------------------------------------------------------------------------
def rollout_threaded_physics(cfg, paths, seed, actions, warmup, threads) -> float:
    """IK, reward and observation serial in Python; the physics substeps of all envs threaded
    through mujoco.rollout (the task's own MjData, left at the final state, as mj_step would)."""
    tasks = [OpenTask(cfg, p, seed + i) for i, p in enumerate(paths)]
    for t in tasks:
        t.reset()
    dec = tasks[0].decimation
    state0 = [np.zeros((1, mujoco.mj_stateSize(t.model, SPEC))) for t in tasks]
    ctrl = [np.zeros((1, dec, t.model.nu)) for t in tasks]
    warm = [np.zeros((1, t.model.nv)) for t in tasks]
    out = [np.zeros((1, dec, s.shape[1])) for s in state0]
    sens = [np.zeros((1, dec, t.model.nsensordata)) for t in tasks]

    def physics(i):
        m, d = tasks[i].model, tasks[i].data
        mujoco.mj_getState(m, d, state0[i][0], SPEC)
        ctrl[i][0, :] = d.ctrl
        warm[i][0] = d.qacc_warmstart
        mujoco.rollout.rollout(
            m, d, state0[i], ctrl[i], initial_warmstart=warm[i], state=out[i], sensordata=sens[i]
        )

    with ThreadPoolExecutor(threads) as ex:
        for s, a in enumerate(actions):
            if s == warmup:
                start = time.perf_counter()
            oks = [t.apply_action(a[i]) for i, t in enumerate(tasks)]
            list(ex.map(physics, range(len(tasks))))
            for t, ok in zip(tasks, oks, strict=True):
                r = t.evaluate(ok)
                if r.terminated or r.truncated:
                    t.reset()
        elapsed = time.perf_counter() - start
    return actions[warmup:].size // 5 / elapsed


def physics_per_step(rec: Recording, warmup: int) -> float:
    """CPU µs per physics step of the recorded run replayed with mujoco.rollout in this thread
    (thread CPU time: other jobs on the machine do not inflate it)."""
    steps, elapsed = 0, 0.0
    dec, chunk = rec.decimation, rec.chunk
    for i, t in enumerate(rec.tasks):
        d = mujoco.MjData(t.model)
        controls = np.repeat(rec.ctrl[i], dec, axis=0)
        for c in range(warmup // chunk, len(rec.state[i])):
            lo, hi = c * chunk * dec, min((c + 1) * chunk, rec.steps) * dec
            start = time.thread_time()
            mujoco.rollout.rollout(
                t.model, d, rec.state[i][c : c + 1], controls[None, lo:hi],
                initial_warmstart=rec.warm[i][c : c + 1],
            )  # fmt: skip
            elapsed += time.thread_time() - start
            steps += hi - lo
    return elapsed / steps * 1e6


# --- report -------------------------------------------------------------------------------------
class RateRow(NamedTuple):
    """One number of envs: control steps per second three ways, measured back to back."""

    envs: int
    steps: int
    best_of: int
    pool: float
    limit: float  # the physics limit: mujoco.rollout on every core
    vec: float  # gymnasium's AsyncVectorEnv
    deviation: float  # replay check: max abs difference of the rollout's state from the recording
    contacts: float  # mean ncon per env after each control step
    pool_start: float  # s
    vec_start: float  # s


class SourceCost(NamedTuple):
    """One collision source's physics cost, single thread."""

    physics_us: float  # per physics step
    contacts: float
    geoms: float  # per scene


@dataclass
class Measured:
    """Everything one run measured: the report is rendered from it alone (--render)."""

    machine: str
    versions: dict[str, str]
    load: tuple[float, float]  # load average at the start and the end
    minutes: float
    cores: int
    rows: list[RateRow]
    profile_envs: int
    profile_rate: float
    profile_limit: float
    parts: list[tuple[str, float]]  # ms per env-step by part (breakdown)
    wall_ms: float  # main process per pool step
    transfer_ms: float  # of which beyond the slowest worker's compute
    core_share: float  # of a core each worker got while stepping
    rollout_us: float  # CPU per physics step in mujoco.rollout
    decimation: int
    design_envs: int
    design_best_of: int
    design: dict[str, float]
    source_envs: int
    sources: dict[str, SourceCost]

    @classmethod
    def from_json(cls, text: str) -> Measured:
        data = json.loads(text)
        data["load"] = tuple(data["load"])
        data["rows"] = [RateRow(*row) for row in data["rows"]]
        data["parts"] = [tuple(part) for part in data["parts"]]
        data["sources"] = {k: SourceCost(*v) for k, v in data["sources"].items()}
        return cls(**data)


PHYSICS_PART = "physics: decimation x mj_step (OpenTask.simulate)"
BOOKKEEPING_PART = "pool bookkeeping (checks, shared-memory writes, episode records)"


def breakdown(seconds: dict, busy: float, env_steps: int) -> list[tuple[str, float]]:
    """ms per env-step by part of the task, and the rest of the pool's step (in-process)."""
    ms = {k: v / env_steps * 1e3 for k, v in seconds.items()}
    ms["busy"] = busy / env_steps * 1e3
    rows = [
        ("IK: mink's QP (built in place, one daqp solve) + its checks", ms["ik"]),
        ("action mapping around the IK (OpenTask.apply_action)", ms["apply"] - ms["ik"]),
        (PHYSICS_PART, ms["simulate"]),
        ("observation (OpenTask.observe, incl. at resets)", ms["observe"]),
        ("reward, terminations, info (rest of OpenTask.evaluate)", ms["evaluate"] - ms["observe"]),
        ("resets (OpenTask.reset, its observation included)", ms["reset"]),
        (
            BOOKKEEPING_PART,
            ms["busy"] - ms["apply"] - ms["simulate"] - ms["evaluate"] - ms["reset"],
        ),
    ]
    return rows


def machine() -> str:
    model = next(
        (
            line.split(":", 1)[1].strip()
            for line in Path("/proc/cpuinfo").read_text().splitlines()
            if line.startswith("model name")
        ),
        platform.processor(),
    )
    return f"{available_cores()} cores ({model}), Python {platform.python_version()}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--envs", type=int, nargs="+", default=[1, 2, 4, 8, 16, 32, 64])
    parser.add_argument("--steps", type=int, default=60, help="control steps per measurement")
    parser.add_argument("--steps-64", type=int, default=30, help="control steps at 64+ envs")
    parser.add_argument("--repeats", type=int, default=2, help="best of, below 64 envs (64: 1)")
    parser.add_argument("--warmup", type=int, default=30, help="untimed control steps first")
    parser.add_argument("--chunk", type=int, default=10, help="control steps per rollout call")
    parser.add_argument("--profile-envs", type=int, default=32)
    parser.add_argument("--design-envs", type=int, default=8)
    parser.add_argument("--source-envs", type=int, default=16, help="configs for CoACD vs hull")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path(__file__).with_suffix(".md"))
    parser.add_argument(
        "--render",
        type=Path,
        metavar="RECORD.json",
        help="write the report again from a run's record, measuring nothing",
    )
    args = parser.parse_args()
    if args.render:
        return render_only(args.render)
    started, load0 = time.perf_counter(), os.getloadavg()
    cores, w = available_cores(), args.warmup
    cfg = load_config(OVERRIDES)
    paths = training_configurations(cfg, max(args.envs + [args.source_envs]), args.seed)

    def record(c, p, steps):
        return Recording(c, p, args.seed, w + steps, args.chunk, w)

    rows = []
    for n in args.envs:
        steps, repeats = (args.steps, args.repeats) if n < 64 else (args.steps_64, 1)
        rec = record(cfg, paths[:n], steps)
        best = np.zeros(3)
        for _ in range(repeats):  # interleaved; best of each, against the other jobs' noise
            pool, pool_start, _ = run_pool(cfg, paths[:n], args.seed, rec.actions, w)
            limit, deviation = physics_limit(rec, cores, w)
            vec, vec_start = async_vector(cfg, paths[:n], args.seed, rec.actions, w)
            best = np.maximum(best, (pool, limit, vec))
        pool, limit, vec = best
        rows.append(
            RateRow(n, steps, repeats, pool, limit, vec, deviation, rec.mean_contacts,
                    pool_start, vec_start)
        )  # fmt: skip
        print(f"{n:3d} envs: pool {pool:7.1f}  physics {limit:7.1f}  async {vec:7.1f} steps/s")

    n = args.profile_envs
    rec = record(cfg, paths[:n], args.steps)
    prof_rate, _, window = run_pool(cfg, paths[:n], args.seed, rec.actions, w)
    prof_limit, _ = physics_limit(rec, cores, w)
    rollout_us = physics_per_step(rec, w)
    seconds, busy = profile_parts(cfg, paths[:n], args.seed, rec.actions, w)
    parts = breakdown(seconds, busy, (len(rec.actions) - w) * n)
    wall_ms = window["wall"] / window["steps"] * 1e3
    transfer_ms = max(window["wall"] - max(window["worker_cpu"]), 0.0) / window["steps"] * 1e3
    print(f"profile at {n}: pool {prof_rate:.1f} steps/s, limit {prof_limit:.1f}")

    n = args.design_envs
    rec = record(cfg, paths[:n], args.steps)
    ways = {
        "pool, one worker process per core": lambda: run_pool(
            cfg, paths[:n], args.seed, rec.actions, w
        )[0],
        "in-process, serial (num_workers=0)": lambda: run_pool(
            cfg, paths[:n], args.seed, rec.actions, w, workers=0
        )[0],
        "in-process, physics threaded via mujoco.rollout": lambda: rollout_threaded_physics(
            cfg, paths[:n], args.seed, rec.actions, w, cores
        ),
        "physics limit (mujoco.rollout, all cores)": lambda: physics_limit(rec, cores, w)[0],
        "physics limit (mujoco.rollout, 1 thread)": lambda: physics_limit(rec, 1, w)[0],
    }
    design = dict.fromkeys(ways, 0.0)
    for _ in range(args.repeats + 1):  # interleaved, best of each
        for name, way in ways.items():
            design[name] = max(design[name], way())
    print("design check:", {k: round(v, 1) for k, v in design.items()})

    n = args.source_envs
    sources = {}
    for source in SOURCES:
        scfg = load_config([*OVERRIDES, f"collision={source}"])
        spaths = [p.with_name(model_name(source)) for p in paths[:n]]
        srec = record(scfg, spaths, args.steps)
        ngeom = float(np.mean([t.model.ngeom for t in srec.tasks]))
        sources[source] = SourceCost(physics_per_step(srec, w), srec.mean_contacts, ngeom)
    print("sources:", sources)

    measured = Measured(
        machine=machine(),
        versions={
            "MuJoCo": mujoco.__version__,
            "mink": importlib.metadata.version("mink"),
            "gymnasium": gym.__version__,
        },
        load=(load0[0], os.getloadavg()[0]),
        minutes=(time.perf_counter() - started) / 60,
        cores=cores,
        rows=rows,
        profile_envs=args.profile_envs,
        profile_rate=prof_rate,
        profile_limit=prof_limit,
        parts=parts,
        wall_ms=wall_ms,
        transfer_ms=transfer_ms,
        core_share=float(np.mean(window["worker_cpu"])) / window["wall"],
        rollout_us=rollout_us,
        decimation=rec.decimation,
        design_envs=args.design_envs,
        design_best_of=args.repeats + 1,
        design=design,
        source_envs=args.source_envs,
        sources=sources,
    )
    atomic_write_text(args.out.with_suffix(".json"), json.dumps(asdict(measured), indent=1) + "\n")
    atomic_write_text(args.out, render(measured))
    print(f"wrote {args.out} and its record {args.out.with_suffix('.json').name}")


def render(m: Measured) -> str:
    """bench_pool.md: the measurements and the figures derived from them; what they mean is in
    experiments/benchmarks/README.md."""
    lines = [
        "# Env pool benchmark",
        "",
        "Command (from the repository root), and what it measured "
        "([`bench_pool.json`](bench_pool.json); reading: [README.md](README.md#env-pool)):",
        "",
        "    python experiments/benchmarks/bench_pool.py",
        "",
        f"Machine: {m.machine}; "
        + ", ".join(f"{name} {v}" for name, v in m.versions.items())
        + f". Load average {m.load[0]:.1f} at the start, {m.load[1]:.1f} at the end (the "
        "machine is shared: compare the columns of one row, measured back to back, not rows "
        f"across runs). Whole run: {m.minutes:.1f} min.",
        "",
        f"Workload: configurations of `{' '.join(OVERRIDES)}` (two-point handles on every base, "
        "CoACD collision), env i on the i-th training draw, a scripted approach-grasp-pull "
        "policy with noise (replayed open-loop by all three), physics step 0.002 s, "
        f"decimation {m.decimation}. Steps/s are control steps summed over the envs. Physics "
        "limit: the recorded physics replayed with `mujoco.rollout` on every core; replay "
        "check: the end state of every rollout chunk against the recorded state. Contacts per env: "
        "mean `ncon` after each control step in the timed window.",
        "",
        "## Control steps per second",
        "",
        "| envs | steps × best of | pool | physics limit | AsyncVectorEnv | pool / physics | "
        "pool / Async | contacts per env | replay max abs dstate | startup pool / Async (s) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *(
            f"| {r.envs} | {r.steps} × {r.best_of} | {r.pool:.0f} | {r.limit:.0f} | {r.vec:.0f} "
            f"| {r.pool / r.limit:.2f} | {r.pool / r.vec:.2f} | {r.contacts:.1f} "
            f"| {r.deviation:.1e} | {r.pool_start:.1f} / {r.vec_start:.1f} |"
            for r in m.rows
        ),
    ]
    at = {r.envs: r for r in m.rows}
    if 32 in at:
        r = at[32]
        lines += [
            "",
            "## Targets at 32 envs",
            "",
            f"- pool ≥ 0.9 × physics limit: {r.pool / r.limit:.2f} — "
            f"**{'met' if r.pool >= 0.9 * r.limit else 'NOT met'}**.",
            f"- pool ≥ 2 × AsyncVectorEnv: {r.pool / r.vec:.2f} — "
            f"**{'met' if r.pool >= 2 * r.vec else 'NOT met'}**.",
            f"- AsyncVectorEnv / physics limit: {r.vec / r.limit:.2f}.",
        ]
    busy = sum(v for _, v in m.parts)
    by_part = dict(m.parts)
    physics, bookkeeping = by_part[PHYSICS_PART], by_part[BOOKKEEPING_PART]
    share, transfer = physics / busy, m.transfer_ms / m.wall_ms
    own = bookkeeping / busy + transfer
    mj_step_us = physics / m.decimation * 1e3
    lines += [
        "",
        f"## Where the time goes ({m.profile_envs} envs, profiled run)",
        "",
        f"Pool {m.profile_rate:.0f} steps/s against a physics limit of {m.profile_limit:.0f} in "
        "this run. CPU time per env-step by part, measured in-process on the same actions with "
        "an instrumented task (thread CPU time, so other jobs on the machine do not inflate "
        f"it). While stepping, the workers got {m.core_share:.0%} of a core each.",
        "",
        "| part | ms per env-step | share |",
        "|---|---:|---:|",
        *(f"| {name} | {value:.3f} | {value / busy:.0%} |" for name, value in m.parts),
        f"| **total per env-step** | **{busy:.3f}** | 100% |",
        "",
        "| derived | value |",
        "|---|---:|",
        f"| main process per pool step: wall | {m.wall_ms:.1f} ms |",
        f"| of which transfer (signalling, shared-memory copies, waiting beyond the slowest "
        f"worker's compute) | {m.transfer_ms:.2f} ms ({transfer:.1%}) |",
        f"| physics, share of the workers' CPU per env-step | {share:.0%} |",
        f"| the pool's own cost (bookkeeping + transfer) | {own:.1%} |",
        f"| ceiling against raw `mj_step` on every core (physics share × (1 − transfer)) "
        f"| {share * (1 - transfer):.2f} |",
        f"| rollout per physics step (CPU, it also records the state) / `mj_step` in the "
        f"workers | {m.rollout_us:.1f} / {mj_step_us:.1f} µs = {m.rollout_us / mj_step_us:.2f}× |",
        f"| ceiling against the rollout limit "
        f"| {min(1.0, share * m.rollout_us / mj_step_us) * (1 - transfer):.2f} |",
        "",
        f"## Design check ({m.design_envs} envs, interleaved, best of {m.design_best_of})",
        "",
        "| how | steps/s |",
        "|---|---:|",
        *(f"| {name} | {value:.0f} |" for name, value in m.design.items()),
    ]
    pool_d, serial_d, threaded_d, limit_d, limit_1 = m.design.values()
    lines += [
        "",
        "| ratio | value |",
        "|---|---:|",
        f"| worker processes / serial loop | {pool_d / serial_d:.2f}× |",
        f"| physics threaded through `mujoco.rollout`, the rest serial / serial loop "
        f"| {threaded_d / serial_d:.2f}× |",
        f"| ceiling on {m.cores} cores, everything but the pool's own cost in parallel "
        f"| {m.cores * (1 - own):.2f}× |",
        f"| ceiling on {m.cores} cores, only the physics in parallel "
        f"| {1 / (1 - share + share / m.cores):.2f}× |",
        f"| pure physics, {m.cores} threads / 1 thread, in this window "
        f"| {limit_d / limit_1:.2f}× |",
    ]
    coacd, hull = m.sources["coacd"], m.sources["hull"]
    lines += [
        "",
        f"## CoACD vs hull physics cost ({m.source_envs} configurations, same scripted "
        "policy, single thread)",
        "",
        "| source | µs per physics step | contacts (mean ncon) | geoms per scene |",
        "|---|---:|---:|---:|",
        *(
            f"| {name} | {c.physics_us:.1f} | {c.contacts:.1f} | {c.geoms:.0f} |"
            for name, c in (("CoACD", coacd), ("hull", hull))
        ),
        "",
        f"CoACD / hull: {coacd.physics_us / hull.physics_us:.2f}× per physics step.",
        "",
    ]
    return "\n".join(lines)


def render_only(record: Path) -> None:
    """Write the report again from a run's record, measuring nothing."""
    atomic_write_text(record.with_suffix(".md"), render(Measured.from_json(record.read_text())))
    print(f"wrote {record.with_suffix('.md')}")


if __name__ == "__main__":
    main()
