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
import os
import platform
import time
from pathlib import Path

for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_name, "1")  # every worker and subprocess single-threaded, alike

import gymnasium as gym  # noqa: E402
import mujoco  # noqa: E402
import numpy as np  # noqa: E402
from pool_record import Measured, RateRow, SourceCost, breakdown  # noqa: E402
from pool_report import write_record, write_report  # noqa: E402
from pool_ways import async_vector, physics_limit, physics_per_step, rollout_threaded_physics  # noqa: E402
from pool_workload import Recording, profile_parts, run_pool  # noqa: E402

from realikea.assets.library import training_configurations  # noqa: E402
from realikea.config import load_config  # noqa: E402
from realikea.pool.env_pool import available_cores  # noqa: E402
from realikea.sources import SOURCES, model_name  # noqa: E402

OVERRIDES = ["asset=two_point", "dr=fixed"]


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


def arguments() -> argparse.Namespace:
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
    return parser.parse_args()


class Bench:
    """One run's settings, configurations and recorded workloads."""

    def __init__(self, args: argparse.Namespace):
        self.args, self.cores, self.warmup = args, available_cores(), args.warmup
        self.cfg = load_config(OVERRIDES)
        envs = max(args.envs + [args.source_envs])
        self.paths = training_configurations(self.cfg, envs, args.seed)

    def record(self, n: int, steps: int, cfg=None, paths=None) -> Recording:
        """The scripted workload of the first `n` configurations, recorded."""
        a = self.args
        cfg, paths = cfg or self.cfg, (paths or self.paths)[:n]
        return Recording(cfg, paths, a.seed, self.warmup + steps, a.chunk, self.warmup)

    def pool(self, rec: Recording, n: int, workers=None):
        return run_pool(self.cfg, self.paths[:n], self.args.seed, rec.actions, self.warmup, workers)


def measure_rates(b: Bench) -> list[RateRow]:
    """Control steps per second three ways, back to back, at every number of envs."""
    a, w, rows = b.args, b.warmup, []
    for n in a.envs:
        steps, repeats = (a.steps, a.repeats) if n < 64 else (a.steps_64, 1)
        rec = b.record(n, steps)
        best = np.zeros(3)
        for _ in range(repeats):  # interleaved; best of each, against the other jobs' noise
            pool, pool_start, _ = b.pool(rec, n)
            limit, deviation = physics_limit(rec, b.cores, w)
            vec, vec_start = async_vector(b.cfg, b.paths[:n], a.seed, rec.actions, w)
            best = np.maximum(best, (pool, limit, vec))
        pool, limit, vec = best
        rows.append(
            RateRow(n, steps, repeats, pool, limit, vec, deviation, rec.mean_contacts,
                    pool_start, vec_start)
        )  # fmt: skip
        print(f"{n:3d} envs: pool {pool:7.1f}  physics {limit:7.1f}  async {vec:7.1f} steps/s")
    return rows


def measure_profile(b: Bench) -> dict:
    """Where the time goes: the pool's window from /proc, the parts of a step in-process."""
    n, w = b.args.profile_envs, b.warmup
    rec = b.record(n, b.args.steps)
    rate, _, window = b.pool(rec, n)
    limit, _ = physics_limit(rec, b.cores, w)
    rollout_us = physics_per_step(rec, w)
    seconds, busy = profile_parts(b.cfg, b.paths[:n], b.args.seed, rec.actions, w)
    print(f"profile at {n}: pool {rate:.1f} steps/s, limit {limit:.1f}")
    return {
        "profile_envs": n,
        "profile_rate": rate,
        "profile_limit": limit,
        "parts": breakdown(seconds, busy, (len(rec.actions) - w) * n),
        "wall_ms": window["wall"] / window["steps"] * 1e3,
        "transfer_ms": max(window["wall"] - max(window["worker_cpu"]), 0.0) / window["steps"] * 1e3,
        "core_share": float(np.mean(window["worker_cpu"])) / window["wall"],
        "rollout_us": rollout_us,
        "decimation": rec.decimation,
    }


def measure_design(b: Bench) -> dict[str, float]:
    """The pool against in-process designs at a few envs, interleaved, best of each."""
    n, w, cores = b.args.design_envs, b.warmup, b.cores
    rec = b.record(n, b.args.steps)
    ways = {
        "pool, one worker process per core": lambda: b.pool(rec, n)[0],
        "in-process, serial (num_workers=0)": lambda: b.pool(rec, n, workers=0)[0],
        "in-process, physics threaded via mujoco.rollout": lambda: rollout_threaded_physics(
            b.cfg, b.paths[:n], b.args.seed, rec.actions, w, cores
        ),
        "physics limit (mujoco.rollout, all cores)": lambda: physics_limit(rec, cores, w)[0],
        "physics limit (mujoco.rollout, 1 thread)": lambda: physics_limit(rec, 1, w)[0],
    }
    design = dict.fromkeys(ways, 0.0)
    for _ in range(b.args.repeats + 1):
        for name, way in ways.items():
            design[name] = max(design[name], way())
    print("design check:", {k: round(v, 1) for k, v in design.items()})
    return design


def measure_sources(b: Bench) -> dict[str, SourceCost]:
    """Each collision source's physics cost per step on the same configurations."""
    n, sources = b.args.source_envs, {}
    for source in SOURCES:
        cfg = load_config([*OVERRIDES, f"collision={source}"])
        paths = [p.with_name(model_name(source)) for p in b.paths[:n]]
        rec = b.record(n, b.args.steps, cfg, paths)
        ngeom = float(np.mean([t.model.ngeom for t in rec.tasks]))
        sources[source] = SourceCost(physics_per_step(rec, b.warmup), rec.mean_contacts, ngeom)
    print("sources:", sources)
    return sources


def main() -> None:
    args = arguments()
    if args.render:
        write_report(Measured.from_json(args.render.read_text()), args.render.with_suffix(".md"))
        return print(f"wrote {args.render.with_suffix('.md')}")
    started, load0 = time.perf_counter(), os.getloadavg()
    b = Bench(args)
    rows = measure_rates(b)
    profile = measure_profile(b)
    design = measure_design(b)
    sources = measure_sources(b)
    measured = Measured(
        machine=machine(),
        versions={
            "MuJoCo": mujoco.__version__,
            "mink": importlib.metadata.version("mink"),
            "gymnasium": gym.__version__,
        },
        load=(load0[0], os.getloadavg()[0]),
        minutes=(time.perf_counter() - started) / 60,
        cores=b.cores,
        rows=rows,
        **profile,
        design_envs=args.design_envs,
        design_best_of=args.repeats + 1,
        design=design,
        source_envs=args.source_envs,
        sources=sources,
    )
    write_record(measured, args.out)
    print(f"wrote {args.out} and its record {args.out.with_suffix('.json').name}")


if __name__ == "__main__":
    main()
