"""The held-out split (realikea/catalog/split.csv): stratified, reproducible, applied by
`asset.split`, defaulting to the test parts in evaluation; and errors that name the bad value or
row."""

from __future__ import annotations

import json
import shutil
from collections import Counter, defaultdict

import pytest
from omegaconf import OmegaConf

from realikea.assets.catalog import Catalog, catalog_dir, effective_split
from realikea.assets.split import (
    SEED,
    SPLIT_FILE,
    make_split,
    read_split,
    split_text,
    with_default_split,
)
from realikea.config import load_config
from realikea.errors import RealIkeaError
from realikea.eval.runs import eval_overrides, rerun_split


def test_committed_split_is_stratified_and_covers_the_catalog(catalog):
    split = catalog.split
    assert set(split) == set(catalog.parts) and set(split.values()) == {"train", "test"}
    by_family = defaultdict(Counter)
    for pid, value in split.items():
        by_family[catalog.parts[pid].family][value] += 1
    assert len(by_family) == 13
    for family, counts in by_family.items():
        n = counts["train"] + counts["test"]
        assert counts["test"] == max(1, round(n / 5)), family
        assert counts["train"] > n / 2, family
    share = sum(v == "test" for v in split.values()) / len(split)
    assert 0.15 <= share <= 0.25
    train = {p for p, v in split.items() if v == "train"}
    test = {p for p, v in split.items() if v == "test"}
    assert not train & test and train | test == set(catalog.parts)


def test_committed_split_is_the_generators_output(catalog):
    assert (catalog_dir() / SPLIT_FILE).read_text() == split_text(
        make_split(catalog.parts.values(), SEED)
    )
    other = make_split(catalog.parts.values(), SEED + 1)
    assert Counter(other.values()) == Counter(catalog.split.values())  # same counts, any seed


def test_held_out_parts_span_the_size_range(catalog):
    """Not all small, not all large: held-out parts sit in both halves of their families."""
    from realikea.assets.split import main_dimension

    halves = Counter()
    for family in {p.family for p in catalog.parts.values()}:
        ranked = sorted(
            (p for p in catalog.parts.values() if p.family == family),
            key=lambda p: (main_dimension(p), p.id),
        )
        for i, p in enumerate(ranked):
            if catalog.split[p.id] == "test":
                halves["small" if i < len(ranked) / 2 else "large"] += 1
    assert halves["small"] >= 4 and halves["large"] >= 4


@pytest.mark.parametrize("category", ["all", "knob", "two_point", "finger_pull"])
def test_split_filters_the_configurations(catalog, category):
    test = list(catalog.configurations(category, split="test"))
    train = list(catalog.configurations(category, split="train"))
    every = list(catalog.configurations(category, split="all"))
    assert test and train
    assert {catalog.split[c.part.id] for c in test} == {"test"}
    assert {catalog.split[c.part.id] for c in train} == {"train"}
    assert {c.id for c in test} | {c.id for c in train} == {c.id for c in every}
    assert not {c.part.id for c in test} & {c.part.id for c in train}


def test_asset_group_defaults_to_train_and_pins_a_part_whatever_its_split(catalog):
    for group in ("all", "knob", "two_point", "finger_pull"):
        assert load_config([f"asset={group}"]).asset.split == "train"
    held_out = next(p for p, v in catalog.split.items() if v == "test")
    pinned = list(catalog.configurations(part=held_out, split="train"))
    assert {c.part.id for c in pinned} == {held_out}
    asset = OmegaConf.create({"category": "all", "part": held_out, "split": "train"})
    assert effective_split(asset, catalog) == "test"


def test_unknown_split_value_lists_the_options(catalog):
    with pytest.raises(RealIkeaError, match=r"unknown asset.split 'val'; choose one of "
                       r"train, test, all"):  # fmt: skip
        list(catalog.configurations(split="val"))
    with pytest.raises(RealIkeaError, match="unknown asset.split 'val'"):
        with_default_split([], "val")


def _copy(tmp_path):
    root = tmp_path / "catalog"
    shutil.copytree(catalog_dir(), root, ignore=shutil.ignore_patterns("imported"))
    return root


def test_an_imported_part_is_test(tmp_path):
    root = _copy(tmp_path)
    folder = root / "imported" / "scan_knob"
    folder.mkdir(parents=True)
    meta = {"id": "scan_knob", "category": "knob", "friction": "plastic"}
    (folder / "part.json").write_text(json.dumps(meta))
    catalog = Catalog.load(root)
    assert catalog.split_of("scan_knob") == "test"
    assert "scan_knob" in {c.part.id for c in catalog.configurations("knob", split="test")}
    assert "scan_knob" not in {c.part.id for c in catalog.configurations("knob", split="train")}


def _rewrite(root, edit):
    lines = (root / SPLIT_FILE).read_text().splitlines()
    (root / SPLIT_FILE).write_text("\n".join(edit(lines)) + "\n")


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda ls: [*ls, "knob_round_99,train"], r"line 85: unknown part 'knob_round_99'"),
        (lambda ls: [ls[0], "knob_round_20,val", *ls[2:]], r"line 2: .*split 'val'; use train"),
        (lambda ls: [ls[0], *ls[2:]], r"no row for catalog part\(s\) knob_round_20"),
        (lambda ls: [*ls, ls[1]], r"line 85: part 'knob_round_20' is listed twice"),
        (
            lambda ls: [
                ls[0],
                *(r.replace(",train", ",test") if "bow" in r else r for r in ls[1:]),
            ],
            "family bow has no train part",
        ),
    ],
)
def test_bad_split_file_names_the_file_and_row(tmp_path, edit, message):
    root = _copy(tmp_path)
    _rewrite(root, edit)
    with pytest.raises(RealIkeaError, match=rf"split\.csv.*{message}"):
        Catalog.load(root)


def test_split_needs_the_file_only_when_filtering(tmp_path):
    root = _copy(tmp_path)
    (root / SPLIT_FILE).unlink()
    catalog = Catalog.load(root)
    assert len(list(catalog.configurations(split="all"))) == 1079
    with pytest.raises(RealIkeaError, match="realikea assets split --write"):
        list(catalog.configurations(split="test"))


def test_read_split_accepts_the_committed_file(catalog):
    parts = list(catalog.parts.values())
    assert read_split(catalog_dir() / SPLIT_FILE, parts) == catalog.split


def test_evaluation_defaults_to_the_test_split():
    from realikea.eval.setup import eval_overrides_with_split, eval_setup
    from realikea.eval.table import cell_config

    assert eval_overrides_with_split(["asset=knob"]) == ["asset=knob", "asset.split=test"]
    assert eval_overrides_with_split(["asset.split=all"]) == ["asset.split=all"]
    cfg, _ = eval_setup(["policy=heuristic_pull", "asset=knob"])
    assert cfg.asset.split == "test" and cfg.asset.category == "knob"
    cfg, _ = eval_setup(["policy=heuristic_pull", "asset.split=train"])
    assert cfg.asset.split == "train"
    assert cell_config([], "heuristic_pull", "knob", "high").asset.split == "test"
    assert cell_config(["asset.split=all"], "heuristic_pull", "knob", "high").asset.split == "all"


def test_eval_after_uses_test_and_an_old_run_all(tmp_path):
    spec = OmegaConf.create({"episodes": 5})
    run = ["asset=knob", "asset.split=all", "resistance=smooth"]
    out = eval_overrides(run, tmp_path / "m.pt", "high", spec)
    assert "asset.split=test" in out and "asset.split=all" not in out
    named = OmegaConf.create({"episodes": 5, "split": "train"})
    assert "asset.split=train" in eval_overrides(run, tmp_path / "m.pt", "high", named)
    old = eval_overrides(run, tmp_path / "m.pt", "high", spec, default_split="all")
    assert "asset.split=all" in old
    hydra = tmp_path / ".hydra"
    hydra.mkdir()
    (hydra / "config.yaml").write_text("asset:\n  category: knob\n  part: null\n")
    assert rerun_split(hydra) == "all"  # a run from before the split: evaluated on every part
    (hydra / "config.yaml").write_text("asset:\n  category: knob\n  split: train\n")
    assert rerun_split(hydra) == "test"
