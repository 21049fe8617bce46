"""`realikea assets verify` and `release --verify`: every exported model reloads in its own tool
(MJCF in MuJoCo, URDF in PyBullet, USD in usd-core) as its metadata.json describes it; a damaged
file is reported by name and the command exits non-zero."""

from __future__ import annotations

import json
import shutil

import pytest
from pxr import Usd

from realikea.cli import main
from realikea.export import FORMATS, release
from realikea.export.driver import export_configurations, export_folder
from realikea.export.release import MANIFEST, VERIFICATION
from realikea.export.verify import verify_folder, verify_release
from realikea.sources import SOURCES

FOLDERS = [f"{fmt}_{source}" for fmt in FORMATS for source in SOURCES]


@pytest.fixture(scope="module")
def released(export_release):
    """A release of the two configurations in every format and source, not verified (shared
    with test_release)."""
    return export_release[0]


@pytest.fixture
def damaged(released, tmp_path):
    """A copy of the release to damage (its files copied: the release's meshes are hard links
    of the shared cache's, never to be written)."""
    out = tmp_path / "release"
    shutil.copytree(released, out)
    return out


def _verification(out) -> dict:
    return json.loads((out / VERIFICATION).read_text())


def _release(export_library, out, *flags) -> int:
    return main(["assets", "release", f"paths.library={export_library}", "--out", str(out), *flags])


# --------------------------------------------------------------------------------- clean


def test_a_clean_release_verifies_and_writes_verification_json(
    export_configs, export_library, tmp_path, monkeypatch, capsys
):
    monkeypatch.setattr(release, "library_configurations", lambda: export_configs)
    out = tmp_path / "release"
    assert _release(export_library, out, "--verify") == 0
    printed = capsys.readouterr().out
    assert "urdf_coacd: verified 2 of 2" in printed
    assert f"verification: {out / VERIFICATION}" in printed
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [release.CARD, MANIFEST, VERIFICATION, *FOLDERS]
    )
    record = _verification(out)
    assert record["failures"] == [] and record["totals"] == {
        "configurations": 12,
        "ok": 12,
        "failed": 0,
    }
    assert set(record["folders"]) == set(FOLDERS)
    for name, counts in record["folders"].items():
        assert (counts["configurations"], counts["ok"], counts["failed"]) == (2, 2, 0)
        assert f"{counts['format']}_{counts['collision']}" == name and counts["seconds"] > 0
    assert record["seconds"] > 0 and all(record["tools"].values())
    assert record["manifest_sha256"] == release.sha256_file(out / MANIFEST)
    # a rerun without --verify leaves no verification of folders it may have changed
    assert _release(export_library, out) == 0
    assert not (out / VERIFICATION).exists() and (out / MANIFEST).is_file()
    assert "not in the manifest" not in capsys.readouterr().out


def test_each_folder_says_what_was_checked(released, export_configs):
    for fmt in FORMATS:
        for source in SOURCES:
            result = verify_folder(export_folder(released, fmt, source, export_configs[1].id), fmt)
            assert result.ok and result.error is None, result.error
            assert result.file.name == f"model_{source}" + {"urdf": ".urdf", "usd": ".usd"}.get(
                fmt, ".xml"
            )
            assert "one per listed convex piece" in result.checked[-1]
            assert "front_joint (hinge)" in " ".join(result.checked)


def test_an_export_folder_without_a_manifest_is_walked(export_configs, export_library, tmp_path):
    export_configurations(export_configs, "usd", "hull", export_library, tmp_path, progress=False)
    report = verify_release(tmp_path, progress=False)
    assert (
        report.ok and report.folders["usd_hull"]["ok"] == 2 and list(report.folders) == ["usd_hull"]
    )
    alone = verify_release(tmp_path / "usd_hull", progress=False)  # the format folder itself
    assert alone.ok and alone.checked == 2


# --------------------------------------------------------------------------------- damaged


def _failures(out) -> dict[str, str]:
    """verification.json's failures: the error by the file it names."""
    return {f["file"]: f["error"] for f in _verification(out)["failures"]}


def test_a_truncated_urdf_fails_by_name_and_the_command_exits_non_zero(
    damaged, export_configs, capsys
):
    urdf = export_folder(damaged, "urdf", "coacd", export_configs[0].id) / "model_coacd.urdf"
    urdf.write_bytes(urdf.read_bytes()[: urdf.stat().st_size // 2])
    assert main(["assets", "verify", str(damaged)]) == 1
    name = urdf.relative_to(damaged).as_posix()
    err = capsys.readouterr().err
    assert "verification failed: 1 of 12 folders" in err and name in err
    failures = _failures(damaged)
    assert list(failures) == [name] and "PyBullet: Cannot load URDF file" in failures[name]
    assert _verification(damaged)["folders"]["urdf_coacd"]["failed"] == 1


def test_a_usd_missing_a_collision_prim_fails_by_name(damaged, export_configs, capsys):
    usd = export_folder(damaged, "usd", "coacd", export_configs[0].id) / "model_coacd.usd"
    stage = Usd.Stage.Open(str(usd))
    part = stage.GetDefaultPrim().GetPath().AppendChild("part")
    assert stage.RemovePrim(part.AppendChild("part_collision_000"))
    stage.GetRootLayer().Save()
    assert main(["assets", "verify", str(damaged)]) == 1
    name = usd.relative_to(damaged).as_posix()
    assert name in capsys.readouterr().err
    (error,) = _failures(damaged).values()
    pieces = len(
        list((usd.parent.parent.parent / "urdf_coacd" / export_configs[0].id).rglob("coacd_*"))
    )
    assert f"{pieces - 1} convexHull collision meshes on the 'part' link" in error
    assert f"urdf_coacd/{export_configs[0].id}/metadata.json lists {pieces} convex pieces" in error


def test_a_mesh_the_mjcf_references_deleted_fails_naming_it(damaged, export_configs, capsys):
    folder = export_folder(damaged, "mjcf", "hull", export_configs[1].id)
    (folder / "meshes" / "hull_000.stl").unlink()
    assert main(["assets", "verify", str(damaged)]) == 1
    name = (folder / "model_hull.xml").relative_to(damaged).as_posix()
    assert name in capsys.readouterr().err
    failures = _failures(damaged)
    assert list(failures) == [name] and "meshes/hull_000.stl" in failures[name]


def test_a_folder_the_manifest_lists_that_is_gone_fails(damaged, export_configs):
    gone = export_folder(damaged, "usd", "hull", export_configs[1].id)
    shutil.rmtree(gone)
    report = verify_release(damaged, progress=False)
    (failure,) = report.failures
    assert failure.folder == gone and failure.error == f"listed in {MANIFEST} but missing"
    assert report.folders["usd_hull"] == {**report.folders["usd_hull"], "ok": 1, "failed": 1}


def test_release_verify_exits_non_zero_when_a_model_does_not_reload(
    export_configs, export_library, tmp_path, monkeypatch, capsys
):
    monkeypatch.setattr(release, "library_configurations", lambda: export_configs)
    out = tmp_path / "release"
    assert _release(export_library, out, "--formats", "mjcf", "--collision", "hull") == 0
    xml = export_folder(out, "mjcf", "hull", export_configs[0].id) / "model_hull.xml"
    xml.write_text("<mujoco/>")  # the release re-exports only when its export key changes
    assert (
        _release(export_library, out, "--formats", "mjcf", "--collision", "hull", "--verify") == 1
    )
    err = capsys.readouterr().err
    assert f"mjcf_hull/{export_configs[0].id}/model_hull.xml: 0 joints" in err
    assert _verification(out)["totals"] == {"configurations": 2, "ok": 1, "failed": 1}


def test_a_folder_that_is_not_an_export_is_refused(tmp_path, capsys):
    assert main(["assets", "verify", str(tmp_path)]) == 2
    assert "holds no exported configuration" in capsys.readouterr().err
    assert main(["assets", "verify", str(tmp_path / "absent")]) == 2
    assert "is not a folder" in capsys.readouterr().err
