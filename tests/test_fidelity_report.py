"""`realikea fidelity report` on one part per category, and its helpers."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.fidelity import commands, heatmap, measure, report
from realikea.files import atomic_path
from realikea.sources import SOURCES

# one part of each category, cheap to decompose (and usually in the project's cache already)
PARTS = ("knob_round_20", "tp_round_bar_64", "fp_edge_64")
FILES = (
    "parts.csv",
    "summary.md",
    "distribution.png",
    "mesh_stats.png",
    "heatmaps_knob.png",
    "heatmaps_two_point.png",
    "heatmaps_finger_pull.png",
)


@pytest.fixture(scope="module")
def small_report(tmp_path_factory):
    """The report on three parts, few samples and coarse heat maps (the project's cache)."""
    out = tmp_path_factory.mktemp("fidelity")
    result = report.run_report(
        load_config(),
        out=out,
        samples=3000,
        seed=1,
        parts_per_category=1,
        parts=PARTS,
        workers=2,
        progress=False,
        command="realikea fidelity report --part ...",
        heat_triangles=6000,
    )
    return out, result


def test_report_writes_every_file_and_nothing_else(small_report):
    out, result = small_report
    assert sorted(p.name for p in out.iterdir()) == sorted(FILES)  # no temporaries left
    assert sorted(p.name for p in result.files) == sorted(FILES)
    for name in FILES:
        assert (out / name).stat().st_size > 0
    for name in FILES:
        if name.endswith(".png"):
            assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not result.failed


def test_parts_csv_rows_and_columns(small_report):
    out, _ = small_report
    with (out / "parts.csv").open(newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
    assert tuple(reader.fieldnames) == measure.COLUMNS
    assert sorted(r["id"] for r in rows) == sorted(PARTS)
    for row in rows:
        assert int(row["hull_pieces"]) == 1
        assert int(row["coacd_pieces"]) >= 1
        assert int(row["visual_faces"]) > 0 and int(row["visual_vertices"]) > 0
        for src in SOURCES:
            for d in measure.DIRECTIONS:
                mean, median, p90, mx = (float(row[f"{src}_{d}_{s}_m"]) for s in measure.STATS)
                assert 0.0 <= median <= p90 <= mx and 0.0 <= mean <= mx
                assert mx < 0.05  # metres: nothing is 5 cm off on a part this size


def test_hull_swells_more_than_coacd_on_a_two_point_handle(small_report):
    _, result = small_report
    bar = next(r for r in result.rows if r["id"] == "tp_round_bar_64")
    # the hull fills the finger gap behind the bar; CoACD keeps it open
    assert bar["hull_q_to_p_mean_m"] > 5 * bar["coacd_q_to_p_mean_m"]
    assert bar["hull_q_to_p_p90_m"] > bar["coacd_q_to_p_p90_m"]
    assert bar["hull_q_to_p_max_m"] > 0.010  # the gap behind the bar is over 1 cm deep


def test_summary_has_the_table_and_the_command(small_report):
    out, result = small_report
    text = (out / "summary.md").read_text()
    assert "| category | parts | metric | CoACD | hull | hull / CoACD |" in text
    for category in ("knob", "two_point", "finger_pull", "all"):
        assert f"| {category} | " in text
    assert "E(Q→P) median" in text and "E(P→Q) mean" in text
    assert "realikea fidelity report --part ..." in text
    assert result.headline in text
    assert "## Mesh statistics" in text


def test_interrupted_write_leaves_no_file(tmp_path):
    def crash(tmp):
        tmp.write_bytes(b"half a PNG")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt), atomic_path(tmp_path / "plot.png") as tmp:
        crash(tmp)
    assert list(tmp_path.iterdir()) == []


def test_split_triangles_keeps_area_and_bounds_edges():
    tris = np.array(
        [[[0, 0, 0], [0.1, 0, 0], [0, 0.002, 0]], [[0, 0, 0], [0, 0, 0.01], [0, 1e-3, 0]]]
    )
    split = heatmap.split_triangles(tris, max_edge=0.004)
    edges = np.linalg.norm(split[:, [1, 2, 0]] - split, axis=2)
    assert edges.max() <= 0.004

    def area(t):
        return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum()

    assert area(split) == pytest.approx(area(tris), rel=1e-12)
    assert len(split) < 400  # midpoint subdivision would need 4^5 = 1024 for the sliver alone
    assert heatmap.split_triangles(tris, max_edge=0.004, limit=10) is None
    assert len(heatmap.split_within(tris, 0.0001, budget=40)) <= 40


def test_heatmap_parts_pick_the_typical_and_the_worst():
    rows = [
        {
            "id": f"p{i}",
            "category": "knob",
            "family": "a" if i < 5 else "b",
            "coacd_q_to_p_mean_m": i,
        }
        for i in range(9)
    ]
    picks = heatmap.heatmap_parts(rows, 2)["knob"]
    assert [r["id"] for r, _ in picks] == ["p4", "p8"]
    assert picks[0][1] == "typical, rank 5/9" and picks[1][1] == "worst CoACD, rank 9/9"
    assert [r["id"] for r, _ in heatmap.heatmap_parts(rows, 1)["knob"]] == ["p4"]
    assert heatmap.heatmap_parts(rows, 0) == {}
    assert len(heatmap.heatmap_parts(rows, 20)["knob"]) == 9


def test_cli_wires_the_options(monkeypatch, tmp_path, capsys):
    from realikea.cli import main

    seen = {}

    def fake(cfg, **kwargs):
        seen.update(kwargs, category=cfg.asset.category)
        return report.ReportResult(tmp_path, [], [tmp_path / "parts.csv"], 0.1, "headline")

    monkeypatch.setattr(commands, "write_report", fake)
    argv = ["fidelity", "report", "--out", str(tmp_path), "--samples", "500", "--seed", "3"]
    argv += ["--parts-per-category", "1", "--part", "knob_round_20", "--part", "fp_edge_64"]
    assert main([*argv, "asset=knob"]) == 0
    assert seen["samples"] == 500 and seen["seed"] == 3 and seen["parts_per_category"] == 1
    assert seen["parts"] == ["knob_round_20", "fp_edge_64"] and seen["category"] == "knob"
    assert seen["command"] == (
        f"realikea fidelity report --out {tmp_path} --samples 500 --seed 3 "
        "--parts-per-category 1 --part knob_round_20 --part fp_edge_64 asset=knob"
    )
    assert "headline" in capsys.readouterr().out


def test_bad_arguments_are_named():
    with pytest.raises(RealIkeaError, match="samples"):
        report.run_report(load_config(), samples=0)
    with pytest.raises(RealIkeaError, match="parts-per-category"):
        report.run_report(load_config(), parts_per_category=-1)
    with pytest.raises(RealIkeaError, match="no_such_part"):
        report.run_report(load_config(), parts=["no_such_part"])
