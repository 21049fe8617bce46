"""`realikea assets` commands end to end, including their errors."""

from __future__ import annotations

import mujoco
import pytest

from realikea.assets.library import read_index
from realikea.cli import main
from realikea.sources import SOURCES


def test_list_prints_the_catalog(capsys):
    assert main(["assets", "list"]) == 0
    out = capsys.readouterr().out
    assert "83 parts" in out and "13 bases" in out and "= 1079 configurations" in out
    assert "drawer_w60_h20" in out and "flap_w60_h40" in out


def test_build_one_configuration_hull_only(catalog, tmp_path, capsys):
    part = catalog.parts_in("finger_pull")[0].id
    args = ["assets", "build", "--part", part, "--base", "flap_w60_h40", "--collision", "hull"]
    assert main([*args, "--out", str(tmp_path)]) == 0
    assert "1 configurations (hull)" in capsys.readouterr().out
    (row,) = read_index(tmp_path)
    assert row["mjcf_coacd"] == "" and row["joint_type"] == "hinge"
    mujoco.MjModel.from_xml_path(str(tmp_path / row["mjcf_hull"]))


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--part", "no_such_handle"], "unknown part id 'no_such_handle'"),
        (["--part", "tp_round_bar_128", "--base", "wardrobe"], "unknown base id 'wardrobe'"),
        (["asset=lever"], "Could not find 'asset/lever'"),
        (["workflow.coacd.threshold=stiff"], "workflow.coacd.threshold='stiff' is not a number"),
        (["resistance=high"], "written at the nominal resistance (normal)"),
    ],
)
def test_build_errors_name_the_input(tmp_path, capsys, args, message):
    assert main(["assets", "build", *args, "--out", str(tmp_path)]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "index.csv").exists()


@pytest.mark.slow
def test_full_library_builds_and_every_mjcf_compiles(tmp_path, capsys):
    """All 1,079 configurations for both sources; a second run is a no-op from cache."""
    assert main(["assets", "build", "--all", "--out", str(tmp_path)]) == 0
    rows = read_index(tmp_path)
    assert len(rows) == 1079
    for row in rows:
        for source in SOURCES:
            mujoco.MjModel.from_xml_path(str(tmp_path / row[f"mjcf_{source}"]))
    capsys.readouterr()
    assert main(["assets", "build", "--all", "--out", str(tmp_path)]) == 0
    assert "parts built 0" in (out := capsys.readouterr().out)
    assert "configurations built 0, up to date 1079" in out


def test_split_prints_the_committed_split(capsys):
    assert main(["assets", "split"]) == 0
    out = capsys.readouterr().out
    assert "67 train, 16 test" in out and "split.csv matches this split" in out
    assert main(["assets", "list"]) == 0
    assert "split (asset.split): 67 train, 16 test" in capsys.readouterr().out
