"""The friction-trap phase map: axis checks, a two-cell map that resumes, its table and plot."""

from __future__ import annotations

import pytest

from realikea.errors import RealIkeaError
from realikea.files import WORKSPACE
from realikea.reports.phase_map import (
    boundary_force,
    difference_grid_lines,
    evaluate_phase_map,
    map_policy,
    phase_table,
    plot_phase_map,
    read_cells,
)

PULL = 20.0  # N: a drawer in high


@pytest.mark.parametrize(
    ("forces", "frictions", "cones", "message"),
    [
        ([-5.0], [0.5], ["elliptic"], "grip force -5.0 N"),
        ([10.0], [2.5], ["elliptic"], "pad friction 2.5"),
        ([10.0], [0.0], ["elliptic"], "pad friction 0.0"),
        ([10.0], [0.5], ["conical"], "friction cone 'conical'"),
    ],
)
def test_out_of_range_axes_are_refused_before_anything_is_written(
    tmp_path, forces, frictions, cones, message
):
    results = tmp_path / "map" / "cells.jsonl"
    with pytest.raises(RealIkeaError, match=message):
        evaluate_phase_map(
            [map_policy("heuristic_pull")], ["two_point"], results, forces, frictions, cones, 1
        )
    assert not results.parent.exists()


def test_policies_are_scripted_names_or_checkpoints(tmp_path):
    with pytest.raises(RealIkeaError, match="scripted policy"):
        map_policy("teleop")
    with pytest.raises(RealIkeaError, match="not found"):
        map_policy(f"coacd={tmp_path / 'missing.pt'}")
    kept = "experiments/fidelity_ablation/results/grid/paper_coacd_high_two_point_s0/model_1300.pt"
    # a checkpoint in the repository is named from its root, so cells.jsonl runs in any clone
    assert map_policy(f"coacd={WORKSPACE / kept}").overrides[1] == f"policy.path={kept}"


def test_the_boundary_is_where_two_pads_carry_the_pull():
    assert boundary_force(0.5, PULL) == 20.0  # 2 x 0.5 x 20 N = 20 N
    assert boundary_force(1.0, PULL) == 10.0


def test_a_two_cell_map_runs_resumes_and_reports(tmp_path):
    results = tmp_path / "cells.jsonl"
    pin = (
        "asset.part=tp_round_bar_128", "asset.base=drawer_w60_h20",
        f"paths.library={tmp_path / 'library'}", "env.num_workers=0", "task.episode_seconds=2",
    )  # fmt: skip
    args = ([map_policy("heuristic_pull")], ["two_point"], results, [70.0], [0.3, 1.0])
    cells = evaluate_phase_map(*args, ["elliptic"], 2, 1000, pin)
    assert len(cells) == 2 and len(results.read_text().splitlines()) == 2
    record = cells[("heuristic_pull", "two_point", "elliptic", 70.0, 0.3)]
    assert record["episodes"] == 2 and "gripper.pad_friction=0.3" in record["command"]
    assert "failure_modes" in record and "slip_ratio" in record
    evaluate_phase_map(*args, ["elliptic"], 2, 1000, pin)  # everything there: nothing runs
    assert len(results.read_text().splitlines()) == 2
    table = "\n".join(phase_table(read_cells(results), PULL))
    assert "| 70 N |" in table and "μ = 0.3" in table and "*" in table  # 2 x 1.0 x 70 >= 20
    png = plot_phase_map(read_cells(results), PULL, tmp_path / "map.png")
    assert png.stat().st_size > 10_000


def test_the_difference_table_bolds_only_intervals_that_exclude_zero():
    def cell(policy, force, success):
        return (policy, "two_point", "elliptic", force, 0.5), {"success": success, "episodes": 20}

    cells = dict(
        [cell("coacd", 70.0, 1.0), cell("hull", 70.0, 0.2), cell("coacd", 5.0, 0.5),
         cell("hull", 5.0, 0.45), cell("grasp_sampler", 5.0, 0.0)]
    )  # fmt: skip
    lines = difference_grid_lines(cells, "coacd", "hull")
    assert lines[0].startswith("**coacd − hull, two_point, elliptic cones**")
    (strong,) = [x for x in lines if x.startswith("| 70 N |")]
    (weak,) = [x for x in lines if x.startswith("| 5 N |")]
    assert strong.startswith("| 70 N | **+0.80 [+") and "**" not in weak
    assert weak.startswith("| 5 N | +0.05 [-")
    assert difference_grid_lines(cells, "hull", "policy_not_mapped") == []
