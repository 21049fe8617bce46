"""Bring your own part: a real mesh joins the library; bad files fail clearly, leaving nothing."""

from __future__ import annotations

import re
import shutil

import mujoco
import numpy as np
import pytest
import trimesh

from realikea.assets.build import WorkflowSettings, build_library
from realikea.assets.catalog import Catalog, catalog_dir
from realikea.cli import main
from realikea.config import load_config
from realikea.sources import SOURCES


@pytest.fixture
def catalog_root(tmp_path, monkeypatch):
    """A private copy of the catalog that `realikea assets import` writes into."""
    root = tmp_path / "catalog"
    shutil.copytree(catalog_dir(), root, ignore=shutil.ignore_patterns("imported"))
    monkeypatch.setenv("REALIKEA_CATALOG", str(root))
    return root


def _mushroom_knob_mm() -> trimesh.Trimesh:
    """A mushroom knob in millimetres, as a CAD export would be: neck and domed head."""
    neck = trimesh.creation.cylinder(radius=6, height=14, sections=64)
    neck.apply_translation([0, 0, 7])
    head = trimesh.creation.icosphere(subdivisions=4, radius=15)
    head.apply_scale([1, 1, 0.5])
    head.apply_translation([0, 0, 20])
    return trimesh.boolean.union([neck, head], engine="manifold")


def _imported(root):
    folder = root / "imported"
    return sorted(p.name for p in folder.iterdir()) if folder.exists() else []


def test_import_builds_like_a_catalog_part(catalog_root, cache_root, tmp_path, capsys):
    """An imported mesh is a catalog part: listed with its configurations and built, its meshes
    cached in the project's content-addressed cache as a catalog part's are (keyed by the mesh
    file's hash: a changed import is built afresh)."""
    source = tmp_path / "scan_knob.stl"
    _mushroom_knob_mm().export(source)
    args = ["assets", "import", str(source), "--category", "knob", "--scale", "0.001"]
    assert main(args) == 0
    assert "imported scan_knob" in capsys.readouterr().out
    catalog = Catalog.load()
    part = catalog.part("scan_knob")
    assert part.category == "knob" and len(catalog.parts) == 84
    assert len(list(catalog.configurations("knob"))) == 13 * len(catalog.parts_in("knob"))
    config = next(catalog.configurations(part="scan_knob", base="drawer_w40_h20"))
    cfg = load_config()
    out = tmp_path / "library"
    build_library(
        [config], WorkflowSettings.from_config(cfg),
        SOURCES, cache_root, out, progress=False,
    )  # fmt: skip
    model = mujoco.MjModel.from_xml_path(str(out / config.id / "model_coacd.xml"))
    visual = trimesh.load_mesh(out / config.id / "meshes" / "visual.obj")
    assert np.isclose(visual.extents.max(), 0.030, atol=1e-3)  # 30 mm head, now in metres
    assert np.isclose(visual.bounds[0][2], 0.0, atol=1e-6)  # sits on the mounting plane
    assert model.nmesh >= 2


def _write(path, text):
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("make", "extra", "message"),
    [
        (lambda d: d / "missing.stl", [], "mesh file not found"),
        (lambda d: _write(d / "notes.txt", "hello"), [], "not a mesh file"),
        (
            lambda d: _write(d / "garbage.obj", "this is not an obj\n"),
            [],
            "no triangles|cannot be read",
        ),
        (lambda d: _open_box(d / "open.stl"), [], "not watertight"),
        (lambda d: _knob_mm(d / "knob_mm.obj"), [], r"millimetres\? try --scale 0.001"),
        (
            lambda d: _knob_mm(d / "knob.obj"),
            ["--scale", "0.001", "--category", "lever"],
            "unknown category 'lever'",
        ),
        (lambda d: _flat(d / "flat.ply"), [], "degenerate|not watertight"),
    ],
)
def test_bad_imports_fail_clearly_and_write_nothing(
    catalog_root, tmp_path, capsys, make, extra, message
):
    path = make(tmp_path)
    category = [] if "--category" in extra else ["--category", "knob"]
    assert main(["assets", "import", str(path), *category, *extra]) == 2
    err = capsys.readouterr().err
    assert re.search(message, err), err
    assert "Traceback" not in err
    assert _imported(catalog_root) == []


def test_duplicate_id_is_refused(catalog_root, tmp_path, capsys):
    source = _knob_mm(tmp_path / "k.obj")
    existing = next(iter(Catalog.load().parts))
    args = ["assets", "import", str(source), "--category", "knob", "--scale", "0.001"]
    assert main([*args, "--id", existing]) == 2
    assert "already exists" in capsys.readouterr().err
    assert _imported(catalog_root) == []


def _open_box(path):
    box = trimesh.creation.box([0.03, 0.02, 0.02])
    box.update_faces(np.arange(len(box.faces)) > 1)  # remove one side: a hole
    box.export(path)
    return path


def _knob_mm(path):
    _mushroom_knob_mm().export(path)
    return path


def _flat(path):
    flat = trimesh.Trimesh([[0, 0, 0], [0.03, 0, 0], [0, 0.03, 0]], [[0, 1, 2], [0, 2, 1]])
    flat.export(path)
    return path


def _round_bar_mm() -> trimesh.Trimesh:
    """A two-point bar handle in millimetres as a CAD export would be: two posts, a bar across."""
    posts = [trimesh.creation.cylinder(radius=5, height=30, sections=48) for _ in range(2)]
    for post, x in zip(posts, (-64, 64), strict=True):
        post.apply_translation([x, 0, 15])
    bar = trimesh.creation.cylinder(radius=6, height=170, sections=48)
    bar.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    bar.apply_translation([0, 0, 30])
    return trimesh.boolean.union([*posts, bar], engine="manifold")


@pytest.mark.parametrize("policy", ["hook_oracle", "heuristic_pull"])
def test_an_imported_handle_opens_a_drawer_and_a_door_in_high(
    catalog_root, tmp_path, capsys, policy
):
    """Bring your own part end to end: a mesh in millimetres, imported, built on a drawer and a
    door, opened in high resistance by the oracle (planning from the mesh) and the pinch."""
    from realikea.eval.protocol import run_episodes
    from realikea.policies.registry import make_policy
    from realikea.pool.env_pool import EnvPool

    source = tmp_path / "my_bar.stl"
    _round_bar_mm().export(source)
    assert (
        main(["assets", "import", str(source), "--category", "two_point", "--scale", "0.001"]) == 0
    )
    for base in ("drawer_w60_h20", "door_right_w60_h80"):
        cfg = load_config(
            [
                f"policy={policy}", "asset.part=my_bar", f"asset.base={base}", "resistance=high",
                "dr=fixed", "contacts.log=true", "env.num_envs=1", "env.num_workers=0",
                f"paths.library={tmp_path / 'library'}",
            ],
            "eval",
        )  # fmt: skip
        with EnvPool.from_config(cfg) as pool:
            episodes = run_episodes(pool, make_policy(cfg), 1, progress=False).episodes
        assert [e["outcome"] for e in episodes] == ["success"], (base, episodes)
        if base.startswith("drawer"):  # on the door the oracle's loop meets the bar obliquely
            expected = "hook" if policy == "hook_oracle" else "pinch"  # (experiments/kitchen)
            assert episodes[0]["strategy"] == expected, (base, episodes[0])
