"""Resistance in one place: the built library carries the nominal mode, a run's mode is applied
where its scene is built, and no run rewrites the library's files."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys

import pytest
from conftest import build_sample

from realikea.errors import RealIkeaError
from realikea.sim.resistance import MODES, NOMINAL, mode, modes, nominal

PART, BASES = "tp_round_bar_128", ("drawer_w60_h20", "door_left_w40_h80")

# one process: draw each base's configuration through the training draw (which builds what is
# missing) and build its scene at the mode given, twice over; print the front joint's
# damping and friction loss per base
DRAW = """
import json, sys
from realikea.assets.library import training_configurations
from realikea.config import load_config
from realikea.sim.scene import FRONT_JOINT, build_scene

resistance, library = sys.argv[1], sys.argv[2]
seen = {}
for _ in range(2):
    for base in sys.argv[3:]:
        cfg = load_config([f"resistance={resistance}", f"paths.library={library}",
                           "asset.part=%s" % "PART", f"asset.base={base}", "asset.split=all"])
        (mjcf,) = training_configurations(cfg, 1)
        model = build_scene(mjcf, cfg)
        dof = model.joint(FRONT_JOINT).dofadr[0]
        seen[base] = [float(model.dof_damping[dof]), float(model.dof_frictionloss[dof])]
print(json.dumps(seen))
""".replace("PART", PART)


def _digest(folder) -> dict[str, str]:
    """SHA-256 of every file under `folder`, by relative path."""
    return {
        str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def test_the_modes_are_the_papers_and_the_nominal_is_the_default():
    assert [(m.name, m.damping, m.frictionloss) for m in modes()] == [
        ("smooth", 2.0, 5.0), ("normal", 5.0, 10.0), ("high", 10.0, 20.0)
    ]  # fmt: skip
    assert NOMINAL in MODES and nominal() == mode("normal")
    with pytest.raises(RealIkeaError, match="unknown resistance mode 'stiff'.*smooth, normal"):
        mode("stiff")


def test_two_runs_at_different_modes_side_by_side_leave_the_library_untouched(
    catalog, settings, cache_root, tmp_path
):
    """Two processes, smooth and high, draw the same configurations at once: each simulates
    its own mode, and the library's files are byte-identical before and after."""
    configs = [next(catalog.configurations(part=PART, base=b)) for b in BASES]
    library = tmp_path / "library"
    build_sample(configs, settings, cache_root, library)
    before = _digest(library)
    runs = {
        m: subprocess.Popen(
            [sys.executable, "-c", DRAW, m, str(library), *BASES],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for m in ("smooth", "high")
    }
    seen = {}
    for m, run in runs.items():
        out, err = run.communicate(timeout=600)
        assert run.returncode == 0, err[-2000:]
        seen[m] = json.loads(out.strip().splitlines()[-1])
    assert _digest(library) == before
    assert seen["smooth"][BASES[0]] == pytest.approx([2.0, 5.0])  # a drawer: the mode as is
    assert seen["high"][BASES[0]] == pytest.approx([10.0, 20.0])
    door_smooth, door_high = seen["smooth"][BASES[1]], seen["high"][BASES[1]]
    assert door_high[1] / door_smooth[1] == pytest.approx(4.0)  # a hinge: scaled by one lever
    assert door_high[0] / door_smooth[0] == pytest.approx(5.0)
