"""The strategy classifier (realikea/tasks/contacts.py) against episodes whose strategy is known
by construction: hook_oracle builds form closure (a loop of fingertips behind a two-point bar, a
wedge behind a finger pull's lip: `hook`; a wedge behind a knob's head: `lever`),
heuristic_pull and grasp_sampler build a friction grasp (`pinch`).

    python experiments/fidelity_ablation/classifier_check.py [--episodes 50] [--seed 0]
        [--tag NAME] [OVERRIDE ...]

Each cell is `realikea eval policy=P asset=C asset.kind=drawer asset.split=test resistance=high
dr=randomized scene=kitchen episodes=N env.seed=S [OVERRIDE ...]`, run in-process. Writes
results/classifier_check[_TAG].md (confusion matrices: rows built, columns label; over the
successful episodes and over those labelled other than `none`, per category and pooled, with the
share labelled as built and its Wilson 95 % interval) and .json (the counts and every episode's
label, outcome and force shares). hook_oracle episodes without a plan (`policy_note`, e.g. a knob
with nothing to get behind) build nothing and are left out (counted under `no_plan`).
"""

from __future__ import annotations

import argparse
import datetime
import json
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

from realikea.assets.library import training_configurations
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.stats import wilson
from realikea.files import atomic_write_text
from realikea.markdown import table
from realikea.tasks.contacts import STRATEGIES

HERE = Path(__file__).resolve().parent
POLICIES = ("hook_oracle", "heuristic_pull", "grasp_sampler")
CATEGORIES = ("two_point", "knob", "finger_pull")
BUILT = ("hook", "lever", "pinch")
KINDS = {"form closure": ("hook", "lever"), "pinch": ("pinch",)}
SUBSETS = {  # which episodes a matrix counts
    "success": lambda e: e["outcome"] == "success",
    "labelled": lambda e: e["label"] != "none",
}
EPISODE_KEYS = ("outcome", "friction_share", "front_share", "pull_seconds", "grip_force")


def built_strategy(policy: str, category: str) -> str:
    """What a policy builds on a category (hook_oracle.py: `catch`, a loop on two-point bars,
    a wedge elsewhere; the wedge behind a knob's head is a lever, behind a lip a hook)."""
    if policy == "hook_oracle":
        return "lever" if category == "knob" else "hook"
    return "pinch"


def cell_overrides(policy: str, category: str, episodes: int, seed: int, extra=()) -> list[str]:
    return [
        f"policy={policy}", f"asset={category}", "asset.kind=drawer", "asset.split=test",
        "resistance=high", "dr=randomized", f"episodes={episodes}", "scene=kitchen",
        f"env.seed={seed}", *extra,
    ]  # fmt: skip


def run_cell(policy: str, category: str, overrides: list[str]) -> list[dict]:
    """One cell's episodes as records: built strategy, label, outcome, force shares, note."""
    cfg, pol = eval_setup(overrides)
    result = evaluate(cfg, pol, progress=False)
    paths = training_configurations(cfg, int(cfg.env.num_envs), int(cfg.env.seed))
    built = built_strategy(policy, category)
    records = []
    for e in result.episodes:
        record = {"policy": policy, "category": category, "built": built}
        record["label"] = e.get("strategy", "none")
        record.update({k: e.get(k) for k in EPISODE_KEYS})
        record["outcome"] = record["outcome"] or "fail"
        record["env"], record["config"] = e["env"], paths[e["env"]].parent.name
        if "policy_note" in e:  # no plan: nothing built
            record["note"] = e["policy_note"]
        records.append(record)
    return records


def confusion(records: list[dict], keep=lambda e: True) -> dict[str, dict[str, int]]:
    """Built strategy -> label -> count over the records `keep` accepts; every row of `BUILT`
    and every label of `STRATEGIES` present (zeros included); records without a plan left out."""
    matrix = {b: dict.fromkeys(STRATEGIES, 0) for b in BUILT}
    for r in records:
        if "note" not in r and keep(r):
            matrix[r["built"]][r["label"]] += 1
    return matrix


def as_built(matrix: dict[str, dict[str, int]], rows=BUILT) -> tuple[int, int]:
    """(labelled as built, total) over the given rows of a confusion matrix."""
    return sum(matrix[b][b] for b in rows), sum(sum(matrix[b].values()) for b in rows)


def share(k: int, n: int) -> str:
    if not n:
        return "-"
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {k / n:.2f} [{lo:.2f}, {hi:.2f}]"


def matrix_table(matrix: dict[str, dict[str, int]]) -> list[str]:
    rows = [
        [b, *(str(matrix[b][s]) for s in STRATEGIES), share(*as_built(matrix, (b,)))]
        for b in BUILT
        if sum(matrix[b].values())
    ]
    header = ["built \\ label", *STRATEGIES, "as built [95 %]"]
    return table(header, "l" + "r" * len(STRATEGIES) + "l", rows)


def groups(records: list[dict]) -> dict[str, list[dict]]:
    """Each category's records, then all of them (`pooled`)."""
    out = {c: [r for r in records if r["category"] == c] for c in CATEGORIES}
    return {**out, "pooled": records}


def counts(records: list[dict]) -> dict:
    """The JSON's numbers: per subset and group, the matrix and each kind's as-built share."""
    out = {}
    for subset, keep in SUBSETS.items():
        for group, rs in groups(records).items():
            m = confusion(rs, keep)
            kinds = {}
            for kind, rows in KINDS.items():
                k, n = as_built(m, rows)
                lo, hi = wilson(k, n) if n else (None, None)
                kinds[kind] = {"as_built": k, "n": n, "share": k / n if n else None,
                               "wilson95": [lo, hi]}  # fmt: skip
            out[f"{subset}/{group}"] = {"matrix": m, "kinds": kinds}
    return out


def cell_lines(records: list[dict]) -> list[str]:
    rows = []
    for p in POLICIES:
        for c in CATEGORIES:
            rs = [r for r in records if r["policy"] == p and r["category"] == c]
            won = sum(r["outcome"] == "success" for r in rs)
            labels = ", ".join(f"{k} {v}" for k, v in Counter(r["label"] for r in rs).items())
            no_plan = sum("note" in r for r in rs)
            rows.append([p, c, str(len(rs)), str(won), str(no_plan), labels])
    header = ["policy", "category", "episodes", "success", "no plan", "labels (all episodes)"]
    return table(header, "llrrrl", rows)


def report(records: list[dict], header: list[str]) -> str:
    numbers = counts(records)
    lines = [*header, "", "## Cells", "", *cell_lines(records)]
    titles = {"success": "successful episodes", "labelled": "episodes labelled other than none"}
    for subset, title in titles.items():
        lines += ["", f"## Over the {title}", ""]
        for kind in KINDS:
            kb = numbers[f"{subset}/pooled"]["kinds"][kind]
            lines.append(f"- pooled, {kind} labelled as built: {share(kb['as_built'], kb['n'])}")
        for group in (*CATEGORIES, "pooled"):
            lines += ["", f"### {group}", "", *matrix_table(numbers[f"{subset}/{group}"]["matrix"])]
    return "\n".join(lines) + "\n"


def commit() -> str:
    git = ["git", "-C", str(HERE), "rev-parse", "--short", "HEAD"]
    sha = subprocess.run(git, capture_output=True, text=True).stdout.strip()
    dirty = ["git", "-C", str(HERE), "status", "--porcelain", "--", "../../realikea"]
    changed = subprocess.run(dirty, capture_output=True, text=True).stdout.strip()
    return sha + (" (realikea/ modified)" if changed else "")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=50, help="episodes a cell")
    parser.add_argument("--seed", type=int, default=0, help="env.seed: the configurations' draw")
    parser.add_argument("--tag", default="", help="results/classifier_check_TAG.{md,json}")
    parser.add_argument("overrides", nargs="*", help="extra overrides, e.g. contacts.min_pull=1")
    args = parser.parse_args()
    records, start, revision = [], time.time(), commit()  # workers import realikea per cell
    for i, (p, c) in enumerate((p, c) for p in POLICIES for c in CATEGORIES):
        t = time.time()
        rs = run_cell(p, c, cell_overrides(p, c, args.episodes, args.seed, args.overrides))
        records += rs
        hits = sum(r["label"] == r["built"] for r in rs)
        print(f"[{i + 1}/9] {p} {c}: {hits}/{len(rs)} labelled {rs[0]['built']}, "
              f"{time.time() - t:.0f} s", flush=True)  # fmt: skip
    command = " ".join(["python", "experiments/fidelity_ablation/classifier_check.py",
                        *sys.argv[1:]])  # fmt: skip
    end = commit()
    at = revision if end == revision else f"{revision} at the start, {end} at the end"
    header = [
        "# Strategy labels against built strategies",
        "",
        f"Command: `{command}` ({args.episodes} episodes a cell, `env.seed={args.seed}`, "
        f"{time.time() - start:.0f} s).  ",
        f"Date: {datetime.date.today()}; commit {at}.  ",
        f"Cells: `{' '.join(cell_overrides('P', 'C', args.episodes, args.seed, args.overrides))}`"
        f" for P in {', '.join(POLICIES)} and C in {', '.join(CATEGORIES)}.",
    ]
    stem = HERE / "results" / ("classifier_check" + (f"_{args.tag}" if args.tag else ""))
    text = report(records, header)
    atomic_write_text(stem.with_suffix(".md"), text)
    data = {"command": command, "date": str(datetime.date.today()), "commit": at,
            "counts": counts(records), "episodes": records}  # fmt: skip
    atomic_write_text(stem.with_suffix(".json"), json.dumps(data, indent=1) + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
