"""The exported URDF in PyBullet behaves as the exported MJCF does in MuJoCo: a front holds below
its breakaway pull and opens above it, opens as far within 10 %, and the fingertip passes behind
a two-point bar with the CoACD pieces and is blocked by the hull."""

from __future__ import annotations

import json

import pytest
from conftest import EXPORT_SAMPLE

from realikea.export.driver import export_configurations, export_folder
from realikea.export.model import read_articulation
from realikea.interop import probe
from realikea.interop.parity import OPENS, SECONDS, STILL, ProbeParity, compare_pull
from realikea.interop.pull import breakaway_force, mujoco_pull, pybullet_pull
from realikea.sim.resistance import mode
from realikea.sources import SOURCES

# the export sample's drawer with a bar (a gap behind it) and door with a knob
CONFIGS = {name: EXPORT_SAMPLE[name] for name in ("drawer", "door")}


@pytest.fixture(scope="module")
def exported(tmp_path_factory, catalog, export_library):
    """The drawer and the door exported to URDF and MJCF in high resistance (the drawer with both
    collision sources) from the session's export library; returns (library, exports,
    configurations by name)."""
    library, out = export_library, tmp_path_factory.mktemp("export")
    configs = {n: next(catalog.configurations(part=p, base=b)) for n, (p, b) in CONFIGS.items()}
    for fmt in ("urdf", "mjcf"):
        for source, chosen in (("coacd", list(configs.values())), ("hull", [configs["drawer"]])):
            export_configurations(
                chosen, fmt, source, library, out, resistance=mode("high"), progress=False
            )
    return library, out, configs


def _front(exported, name: str, source: str = "coacd"):
    """(MJCF, URDF, metadata, handle, breakaway force) of one exported front."""
    _, out, configs = exported
    config_id = configs[name].id
    folder = export_folder(out, "urdf", source, config_id)
    metadata = json.loads((folder / "metadata.json").read_text())
    mjcf = export_folder(out, "mjcf", source, config_id) / f"model_{source}.xml"
    handle = read_articulation(mjcf).handle
    joint = metadata["joint"]
    frictionloss = metadata["resistance"]["exported"]["frictionloss"]
    force = breakaway_force(joint["type"], frictionloss, joint["anchor"], joint["axis"], handle)
    return mjcf, folder / f"model_{source}.urdf", metadata, handle, force


def _pybullet(exported, name: str, multiple: float, **options):
    """PyBullet's trajectory under `multiple` x the front's breakaway pull."""
    _, urdf, metadata, handle, force = _front(exported, name)
    joint = metadata["joint"]
    return pybullet_pull(
        urdf, handle, joint["anchor"], joint["axis"], multiple * force, SECONDS, **options
    )


@pytest.mark.parametrize("name", list(CONFIGS))
def test_pybullet_front_holds_at_half_and_opens_at_twice_its_breakaway_pull(exported, name):
    """With the friction emulated, PyBullet keeps MuJoCo's breakaway: still at 0.5x, open at 2x."""
    joint_type = _front(exported, name)[2]["joint"]["type"]
    assert abs(_pybullet(exported, name, 0.5).at(SECONDS)) < STILL[joint_type]
    assert _pybullet(exported, name, 2.0).at(SECONDS) >= OPENS[joint_type]


@pytest.mark.parametrize("name", list(CONFIGS))
@pytest.mark.parametrize("multiple", [0.5, 1.2, 2.0])
def test_pybullet_opens_as_far_as_mujoco_within_ten_percent(exported, name, multiple):
    """After 1 s and, where the front reaches its stop, before it (at MuJoCo's half range)."""
    mjcf, _, metadata, _, force = _front(exported, name)
    joint = metadata["joint"]
    reference = mujoco_pull(mjcf, multiple * force, SECONDS)
    other = _pybullet(exported, name, multiple)
    assert other.timestep == reference.timestep
    expected = "still" if multiple < 1 else "opens"
    result = compare_pull(reference, other, joint["type"], joint["range"][1], expected)
    assert result.passed, result


def test_pybullet_without_the_emulation_ignores_the_urdf_friction(exported):
    """Why the friction is emulated: PyBullet's own joint motor locks the front at twice its
    breakaway pull, and without a motor it opens at half of it."""
    assert _pybullet(exported, "drawer", 2.0, friction="default").at(SECONDS) == pytest.approx(
        0.0, abs=1e-6
    )
    assert _pybullet(exported, "drawer", 0.5, friction="ignored").at(SECONDS) > OPENS["slide"]


@pytest.mark.parametrize("source", SOURCES)
def test_fingertip_passes_behind_the_bar_with_coacd_and_is_blocked_by_the_hull(exported, source):
    """The 9 mm pad gets behind the bar through the CoACD pieces, not the hull, in both."""
    _, urdf, metadata, _, _ = _front(exported, "drawer", source)
    path = probe.ProbePath.from_metadata(metadata)
    result = ProbeParity(
        "passes" if source == "coacd" else "blocked",
        path.through,
        probe.mujoco_probe(probe.part_pieces(urdf), path),
        probe.pybullet_probe(urdf, path),
    )
    assert result.outcome(result.pybullet) == result.expected, result
    assert result.passed, result
