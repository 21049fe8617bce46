"""`realikea assets release`: every format and collision source, DATASET.md and a manifest whose
checksums match the files; reruns export nothing and rewrite the same manifest; an interrupted
release leaves no manifest; bad input is refused before anything is written; the dataset
card's YAML header parses and quotes the catalog's counts."""

from __future__ import annotations

import hashlib
import json
import re
import shutil

import pytest
import yaml

from realikea.cli import main
from realikea.errors import RealIkeaError
from realikea.export import FORMATS, release
from realikea.export.driver import export_folder
from realikea.export.release import (
    CARD,
    MANIFEST,
    catalog_counts,
    release_library,
)
from realikea.files import repo_path
from realikea.sources import SOURCES

FOLDERS = [f"{fmt}_{source}" for fmt in FORMATS for source in SOURCES]
TITLE = "Real-IKEA: Physical Fidelity is the Prerequisite for Robust Manipulation"


@pytest.fixture(scope="module")
def released(export_release):
    """A release of the two configurations in every format and source, and its report (shared
    with test_verify: a rerun into it rewrites the same files)."""
    return export_release


def _manifest(out) -> dict:
    return json.loads((out / MANIFEST).read_text())


def _entries(manifest: dict) -> list[dict]:
    """Every file entry of a manifest."""
    exports = [e for c in manifest["configurations"].values() for e in c["exports"].values()]
    return manifest["files"] + [f for e in exports for f in e["files"]]


def _files(out) -> set[str]:
    return {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}


def _header(text: str) -> dict:
    """The YAML front matter of a Markdown file."""
    match = re.match(r"---\n(.*?)\n---\n", text, flags=re.S)
    assert match, "no YAML front matter"
    return yaml.safe_load(match.group(1))


# --------------------------------------------------------------------------------- the release


def test_the_release_holds_every_format_and_source_the_card_and_a_matching_manifest(
    released, export_configs
):
    out, report = released
    assert sorted(p.name for p in out.iterdir()) == sorted([CARD, MANIFEST, *FOLDERS])
    assert (out / CARD).read_bytes() == repo_path(CARD).read_bytes()
    assert report.exported == dict.fromkeys(FOLDERS, 2) and report.unlisted == []
    manifest = _manifest(out)
    entries = _entries(manifest)
    # one entry per file of the release but the manifest itself, each matching its file
    assert sorted(e["path"] for e in entries) == sorted(_files(out) - {MANIFEST})
    for entry in entries:
        data = (out / entry["path"]).read_bytes()
        assert entry["size"] == len(data)
        assert entry["sha256"] == hashlib.sha256(data).hexdigest()
    totals = manifest["totals"]
    assert (totals["files"], totals["bytes"]) == (report.files, report.bytes)
    assert totals["files"] == len(entries) and totals["bytes"] == sum(e["size"] for e in entries)
    assert totals["configurations"] == 2
    for name, folder in totals["folders"].items():
        records = manifest["configurations"].values()
        listed = [f for c in records for f in c["exports"][name]["files"]]
        assert folder["configurations"] == 2 and folder["files"] == len(listed)
    for config in export_configs:
        record = manifest["configurations"][config.id]
        assert (record["part_id"], record["base_id"]) == (config.part.id, config.base.id)
        assert record["resistance_mode"] == "normal"  # the default: the nominal mode
        assert sorted(record["exports"]) == sorted(FOLDERS)
        for fmt in FORMATS:
            for source in SOURCES:
                folder = export_folder(out, fmt, source, config.id)
                metadata = json.loads((folder / "metadata.json").read_text())
                assert record["fidelity_certificate"][source] == metadata["fidelity_certificate"]
                model = record["exports"][f"{fmt}_{source}"]["model"]
                assert (out / model).is_file() and model.endswith(metadata["export"]["model"])


def test_a_rerun_exports_nothing_and_rewrites_the_same_manifest(
    released, export_configs, export_library
):
    out, _ = released
    before = (out / MANIFEST).read_bytes()
    stamps = {p: p.stat().st_mtime_ns for p in out.rglob("metadata.json")}
    again = release_library(export_configs, export_library, out, progress=False)
    assert again.exported == dict.fromkeys(FOLDERS, 0)
    assert again.current == dict.fromkeys(FOLDERS, 2)
    assert (out / MANIFEST).read_bytes() == before
    assert {p: p.stat().st_mtime_ns for p in out.rglob("metadata.json")} == stamps


def test_an_interrupted_release_leaves_no_manifest_and_resumes(
    export_configs, export_library, tmp_path, monkeypatch
):
    out = tmp_path / "release"
    out.mkdir()
    (out / MANIFEST).write_text('{"stale": true}')  # from an earlier release
    exported = release.export_configurations
    calls = []

    def crash_on_the_third(*args, **kwargs):
        calls.append(args[1:3])
        if len(calls) == 3:
            raise KeyboardInterrupt
        return exported(*args, **kwargs)

    monkeypatch.setattr(release, "export_configurations", crash_on_the_third)
    with pytest.raises(KeyboardInterrupt):
        release_library(export_configs, export_library, out, progress=False)
    assert not (out / MANIFEST).exists()
    assert sorted(p.name for p in out.iterdir()) == FOLDERS[:2]  # no staging folder left
    monkeypatch.setattr(release, "export_configurations", exported)
    report = release_library(export_configs, export_library, out, progress=False)
    assert report.exported == {name: 0 if name in FOLDERS[:2] else 2 for name in FOLDERS}
    assert _manifest(out)["totals"]["folders"].keys() == set(FOLDERS)


def test_a_folder_changed_after_its_export_is_refused(
    released, export_configs, export_library, tmp_path
):
    out = tmp_path / "release"
    shutil.copytree(released[0], out)
    stray = export_folder(out, "urdf", "hull", export_configs[0].id) / "notes.txt"
    stray.write_text("mine")
    with pytest.raises(RealIkeaError, match=r"urdf_hull/tp_round_bar_128__drawer_w60_h20.*notes"):
        release_library(export_configs, export_library, out, progress=False)
    assert not (out / MANIFEST).exists()


def test_the_command_releases_the_selected_formats_and_sources(
    export_configs, export_library, tmp_path, monkeypatch, capsys
):
    monkeypatch.setattr(release, "library_configurations", lambda: export_configs)
    out = tmp_path / "release"
    args = ["--out", str(out), "--formats", "mjcf", "urdf", "--collision", "hull"]
    assert main(["assets", "release", f"paths.library={export_library}", *args]) == 0
    printed = capsys.readouterr().out
    assert "mjcf_hull: exported 2, up to date 0" in printed and "manifest:" in printed
    assert sorted(p.name for p in out.iterdir()) == [CARD, MANIFEST, "mjcf_hull", "urdf_hull"]
    manifest = _manifest(out)
    assert (manifest["formats"], manifest["collision_sources"]) == (["mjcf", "urdf"], ["hull"])


# --------------------------------------------------------------------------------- bad input


def test_an_unknown_format_or_source_is_refused_before_writing(
    export_configs, export_library, tmp_path, capsys
):
    out = tmp_path / "release"
    with pytest.raises(RealIkeaError, match="unknown export format 'obj'.*urdf, usd, mjcf"):
        release_library(export_configs, export_library, out, ["urdf", "obj"], progress=False)
    with pytest.raises(RealIkeaError, match="unknown collision source 'vhacd'"):
        release_library(export_configs, export_library, out, sources=["vhacd"], progress=False)
    with pytest.raises(RealIkeaError, match="no format to release"):
        release_library(export_configs, export_library, out, [], progress=False)
    with pytest.raises(SystemExit):
        main(["assets", "release", "--out", str(out), "--formats", "obj"])
    assert "invalid choice: 'obj'" in capsys.readouterr().err
    assert not out.exists()


def test_an_out_that_is_a_file_is_refused(
    export_configs, export_library, tmp_path, monkeypatch, capsys
):
    monkeypatch.setattr(release, "library_configurations", lambda: export_configs)
    out = tmp_path / "taken.txt"
    out.write_text("mine")
    assert main(["assets", "release", f"paths.library={export_library}", "--out", str(out)]) == 2
    assert f"--out {out} is an existing file" in capsys.readouterr().err
    assert out.read_text() == "mine" and sorted(tmp_path.iterdir()) == [out]


def test_configurations_not_built_are_refused_with_how_to_build_them(
    export_configs, catalog, export_library, tmp_path, monkeypatch, capsys
):
    unbuilt = next(catalog.configurations(part="knob_round_20", base="flap_w60_h40"))
    monkeypatch.setattr(release, "library_configurations", lambda: [*export_configs, unbuilt])
    out = tmp_path / "release"
    assert main(["assets", "release", f"paths.library={export_library}", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "1 of 3 configurations are not built" in err
    assert "realikea assets build --part knob_round_20 --base flap_w60_h40" in err
    assert not out.exists()


def test_a_missing_card_or_out_is_refused(export_configs, export_library, tmp_path, capsys):
    out = tmp_path / "release"
    with pytest.raises(RealIkeaError, match="dataset card .*no_card.md does not exist"):
        release_library(
            export_configs, export_library, out, card=tmp_path / "no_card.md", progress=False
        )
    assert main(["assets", "release"]) == 2
    assert "--out DIR" in capsys.readouterr().err
    assert not out.exists()


# --------------------------------------------------------------------------------- the card


def test_the_dataset_card_header_parses_with_the_licence_and_the_catalog_counts():
    text = repo_path(CARD).read_text()
    header = _header(text)
    # the licence: what the repository declares, which is none
    pyproject = repo_path("pyproject.toml").read_text()  # tomllib is 3.11+, the project 3.10+
    declared = re.search(r"^license(-files)?\s*=", pyproject, flags=re.M) or any(
        repo_path(".").glob("LICEN[CS]E*")
    )
    assert not declared, "the repository now declares a licence: say which in DATASET.md"
    assert header["license"] == "unknown"
    assert set(header["licenses"]) == {"meshes", "models"}
    assert all("none declared" in v for v in header["licenses"].values())
    # the counts are the catalog's, as `realikea assets release --counts` prints them
    counts = header["counts"]
    assert counts == catalog_counts()
    assert counts["configurations"] == counts["parts"] * counts["bases"]
    assert header["size_categories"] == ["1K<n<10K"] and 1_000 < counts["configurations"] < 10_000
    assert "robotics" in header["task_categories"] and header["pretty_name"]
    assert TITLE in text


def test_the_counts_command_prints_the_card_header_counts(capsys):
    assert main(["assets", "release", "--counts"]) == 0
    printed = yaml.safe_load(capsys.readouterr().out)
    assert printed == {"counts": _header(repo_path(CARD).read_text())["counts"]}
