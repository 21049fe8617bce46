"""Committed checkpoints: each study's manifest matches its files, every checkpoint is cited,
none carries optimiser state outside a parked folder; and the citation and command rules."""

from __future__ import annotations

import pytest
import torch
import yaml

from realikea.errors import RealIkeaError
from realikea.files import WORKSPACE
from realikea.runs.citations import citations
from realikea.runs.manifest import (
    manifest_rows,
    read_manifest,
    run_command,
    study_checkpoints,
    write_manifest,
)

STUDIES = [s for s in sorted((WORKSPACE / "experiments").iterdir()) if study_checkpoints(s)]


def save_checkpoint(path, resumable=False):
    path.parent.mkdir(parents=True, exist_ok=True)
    saved = {"actor_state_dict": {"w": torch.zeros(2)}, "iter": 0, "infos": None}
    if resumable:
        saved["optimizer_state_dict"] = {}
    torch.save(saved, path)
    return path


def hydra_record(run, hydra, task):
    (run / ".hydra").mkdir(parents=True, exist_ok=True)
    record = {"hydra": {"overrides": {"hydra": hydra, "task": task}}}
    (run / ".hydra/hydra.yaml").write_text(yaml.safe_dump(record))


@pytest.mark.parametrize("study", STUDIES, ids=lambda s: s.name)
def test_each_study_manifest_matches_its_checkpoints(study):
    assert read_manifest(study) == manifest_rows(study), (
        f"{study.name}: results/checkpoints.csv is stale; "
        "python experiments/tools/checkpoints.py --write"
    )


def test_every_committed_checkpoint_is_cited_and_slim_unless_parked():
    found = [p for study in STUDIES for p in study_checkpoints(study)]
    uncited = [p for p, by in citations(WORKSPACE, found).items() if not by]
    assert uncited == [], "cite them (a path or pattern in a doc) or prune them"
    rows = [(s, r) for s in STUDIES for r in read_manifest(s)]
    full = [r["checkpoint"] for s, r in rows if r["resumable"] == "yes"]
    assert all("_parked/" in path for path in full), full


def test_a_checkpoint_is_cited_by_path_pattern_own_result_or_table_row(tmp_path):
    study = tmp_path / "experiments/study"
    runs = {
        name: save_checkpoint(study / f"results/runs/{name}/model_99.pt")
        for name in ("by_path", "by_pattern_s0", "by_result", "by_row", "uncited_run", "logged")
    }
    (tmp_path / "README.md").write_text(
        "policy.path=experiments/study/results/runs/by_path/model_99.pt\n"
        "seeds: `results/runs/by_pattern_s${seed}/model_99.pt`\n"
        "a file name alone cites nothing: model_99.pt\n"
    )
    (study / "results/runs/by_result/sweep.jsonl").write_text('{"iteration": 99}\n')
    (study / "results/table.md").write_text("| by_row | model_99.pt | 0.5 |\n")
    (study / "results/runs/logged/metrics.csv").write_text("logged,model_99.pt\n")
    (study / "results/runs/uncited_run/.hydra").mkdir()
    (study / "results/runs/uncited_run/.hydra/config.yaml").write_text("resume: model_99.pt\n")
    cited = citations(tmp_path, list(runs.values()))
    assert cited[runs["by_path"]] == ["README.md"]
    assert cited[runs["by_pattern_s0"]] == ["README.md"]
    assert cited[runs["by_result"]] == ["experiments/study/results/runs/by_result/sweep.jsonl"]
    assert cited[runs["by_row"]] == ["experiments/study/results/table.md"]
    assert cited[runs["uncited_run"]] == [] and cited[runs["logged"]] == []


def test_the_command_comes_from_hydra_then_the_study_record_else_an_error(tmp_path):
    study = tmp_path / "study"
    typed = study / "results/typed"
    hydra_record(typed, ["hydra.run.dir=out/a b", "hydra.mode=RUN"], ["env.seed=3"])
    assert run_command(study, typed, {}) == "python train.py 'hydra.run.dir=out/a b' env.seed=3"
    listed = study / "results/old/s0"
    listed.mkdir(parents=True)
    assert run_command(study, listed, {"old/s0": "python train.py x=1"}) == "python train.py x=1"
    with pytest.raises(RealIkeaError, match="old/s0"):
        run_command(study, listed, {})
    staged = study / "results/staged"  # a pipeline's launch, stopped before any stage ended
    hydra_record(staged, [], ["env.seed=20"])
    (staged / ".hydra/config.yaml").write_text("pipeline: {name: distilled_pairs}\n")
    (staged / "teacher_door").mkdir()
    assert run_command(study, staged / "teacher_door", {}) == run_command(study, staged, {})
    single = study / "results/single"
    hydra_record(single, [], ["env.seed=20"])
    (single / ".hydra/config.yaml").write_text("pipeline: {name: none}\n")
    (single / "teacher_door").mkdir()
    with pytest.raises(RealIkeaError, match="single/teacher_door"):  # not a staged run's stage
        run_command(study, single / "teacher_door", {})


def test_the_manifest_records_sha_resume_source_and_whether_training_resumes(tmp_path):
    study = tmp_path / "study"
    path = save_checkpoint(study / "results/r/model_49.pt", resumable=True)
    hydra_record(path.parent, [], ["train.resume=out/r/model_24.pt", "agent.max_iterations=25"])
    write_manifest(study)
    (row,) = read_manifest(study)
    assert row["checkpoint"] == "results/r/model_49.pt" and row["iteration"] == "49"
    assert row["resumable"] == "yes" and row["resumed_from"] == "out/r/model_24.pt"
    assert len(row["sha256"]) == 64 and int(row["bytes"]) == path.stat().st_size
    assert read_manifest(study) == manifest_rows(study)
