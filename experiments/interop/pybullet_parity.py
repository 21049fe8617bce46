"""The exported URDFs in PyBullet against the exported MJCFs in MuJoCo; writes results/pybullet.md
(tables) and results/pybullet_figures.json (the figures the README quotes).

    nice -n 10 python experiments/interop/pybullet_parity.py [--work DIR] [--out FILE]

A sample of six configurations (two per kind, every category twice) is built into a scratch
library (`--work`, a temporary folder by default; part meshes come from the project's cache) and
exported to URDF and MJCF at each resistance mode with `realikea/export`. Each is pulled at its
handle with 0.5x, 1.2x and 2x its breakaway force for 1 s in both simulators (same pull, same
2 ms step, gravity on). Every two-point part on `drawer_w60_h20`, plus the sample's door, is then
probed with the Franka Hand's 9 mm fingertip in both simulators with both collision sources. Last,
what PyBullet does not express is measured: its own joint motor and the ignored URDF friction,
its damping against a damping applied by hand, joint limits, creep, and collision margins.
"""

from __future__ import annotations

import json
import resource
import sys
import tempfile
import time
from importlib.metadata import version
from pathlib import Path

from parity_figures import figures
from parity_measure import clearances, probes, pulls
from parity_report import report
from parity_unexpressed import unexpressed

from realikea.files import atomic_write_text, repo_path
from realikea.interop.sample import SAMPLE_MODES, prepare, sample_arguments, sample_context
from realikea.sources import SOURCES

DEFAULT_OUT = repo_path("experiments/interop/results/pybullet.md")
PROBE_BASE = "drawer_w60_h20"  # every two-point part is probed on this base
COMMAND = "nice -n 10 python experiments/interop/pybullet_parity.py"


def main(argv=None) -> int:
    """Run the sample and write the tables and the figures."""
    args = sample_arguments(__doc__.split("\n\n")[0], DEFAULT_OUT, argv)
    start, cpu = time.perf_counter(), time.process_time()
    settings, cache_root, catalog, sample = sample_context()
    probed = [
        c for p in catalog.parts_in("two_point") for c in catalog.configurations(part=p.id,
                                                                               base=PROBE_BASE)
    ]  # fmt: skip
    with tempfile.TemporaryDirectory(prefix="realikea_parity_") as scratch:
        work = args.work or Path(scratch)
        prepared = {
            mode: prepare(sample, mode, ("coacd",), work, settings, cache_root)
            for mode in SAMPLE_MODES
        }
        to_probe = [c for c in sample if c.part.category == "two_point" and c not in probed]
        probe_set = prepare(probed + to_probe, "high", SOURCES, work, settings, cache_root)
        print("built and exported", flush=True)
        pulled = [p for mode in SAMPLE_MODES for p in pulls(prepared[mode])]
        print("pulls done", flush=True)
        probed_runs, clear = probes(probe_set), clearances(probe_set)
        print("probes done", flush=True)
        found = unexpressed(prepared["high"])
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu + children.ru_utime + children.ru_stime
    versions = {"pybullet": version("pybullet"), "mujoco": version("mujoco")}
    provenance = (
        f"Written by `{COMMAND}` ({wall:.0f} s wall, {cpu:.0f} s CPU on the shared 2-core "
        f"machine); PyBullet {versions['pybullet']}, MuJoCo {versions['mujoco']}."
    )
    made = {"command": COMMAND, "versions": versions, "wall_s": wall, "cpu_s": cpu}
    atomic_write_text(args.out, report(pulled, probed_runs, clear, found, provenance))
    data = figures(pulled, probed_runs, clear, found, made)
    figures_path = args.out.with_name(args.out.stem + "_figures.json")
    atomic_write_text(figures_path, json.dumps(data, indent=2, allow_nan=False) + "\n")
    print(f"wrote {args.out} and {figures_path.name} ({wall:.0f} s wall, {cpu:.0f} s CPU)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
