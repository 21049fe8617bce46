"""One checkpoint over the library's grid, kind x category x resistance mode, on the held-out parts.

`evaluate_grid` runs `realikea eval` (its own setup: the checkpoint's run groups, the strategy
classifier) once per cell and appends the cell's JSON line to a results file as it goes, so an
interrupted grid continues where it stopped. `success_table` turns a results file into the table
with Wilson intervals, `difference_markdown` two of them (CoACD, hull) into the difference per cell
with Newcombe's interval.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, effective_split
from realikea.eval.runs import run_scene
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.stats import count, diff_interval, significant, wilson
from realikea.files import shown_path
from realikea.sim.resistance import MODES
from realikea.tasks.outcome import OUTCOMES

KINDS = tuple(BASE_KINDS)  # drawer, door, flap


def cell_overrides(
    checkpoint: Path,
    kind: str,
    category: str,
    mode: str,
    episodes: int,
    seed: int,
    extra: list[str],
) -> list[str]:
    """`realikea eval` overrides of one cell: test parts, randomized poses, a held-out seed, in
    the scene the checkpoint's run was trained in (`run_scene`, when its `.hydra` sits beside
    it: a placement changed since does not move its arm)."""
    hydra = Path(checkpoint).parent / ".hydra"
    scene = run_scene(hydra) if (hydra / "config.yaml").is_file() else []
    return [
        "policy=checkpoint", f"policy.path={shown_path(Path(checkpoint).resolve())}",
        f"asset={category}", f"asset.kind={kind}", f"resistance={mode}", "asset.split=test",
        "dr=randomized", f"episodes={episodes}", f"env.seed={seed}", *scene, *extra,
    ]  # fmt: skip


def read_cells(results: Path) -> dict[tuple[str, str, str], dict]:
    """(kind, category, mode) -> the cell's record, from a results file (JSON lines)."""
    if not Path(results).is_file():
        return {}
    records = [json.loads(line) for line in Path(results).read_text().splitlines() if line]
    return {(r["kind"], r["category"], r["resistance"]): r for r in records}


def evaluate_grid(
    checkpoint: Path,
    results: Path,
    episodes: int = 50,
    seed: int = 1000,
    kinds=KINDS,
    categories=CATEGORIES,
    modes=MODES,
    extra: list[str] | None = None,
) -> dict[tuple[str, str, str], dict]:
    """Evaluate every cell missing from `results`, appending one JSON line per cell."""
    results = Path(results)
    results.parent.mkdir(parents=True, exist_ok=True)
    done = read_cells(results)
    todo = [(k, c, m) for k in kinds for c in categories for m in modes if (k, c, m) not in done]
    for n, (kind, category, mode) in enumerate(todo, 1):
        overrides = cell_overrides(checkpoint, kind, category, mode, episodes, seed, extra or [])
        start = time.perf_counter()
        cfg, policy = eval_setup(overrides)
        summary = evaluate(cfg, policy, progress=False).summary()
        record = {
            "kind": kind, "category": category, "resistance": mode,
            "collision": str(cfg.collision.source), "scene": str(cfg.scene.name),
            "split": effective_split(cfg.asset), "seed": seed, **summary,
            "seconds": round(time.perf_counter() - start, 1),
            "command": "realikea eval " + " ".join(overrides),
        }  # fmt: skip
        with results.open("a") as f:
            f.write(json.dumps(record) + "\n")
        done[(kind, category, mode)] = record
        print(
            f"[{n}/{len(todo)}] {kind} {category} {mode}: "
            + " ".join(f"{o} {summary[o]:.2f}" for o in OUTCOMES),
            flush=True,
        )
    return done


def _count(record: dict) -> tuple[int, int]:
    """Successes and episodes of a cell (its success rate is k / n of its episodes)."""
    n = int(record["episodes"])
    return count(record["success"], n), n


def _rate(record: dict | None) -> str:
    if record is None:
        return "–"
    k, n = _count(record)
    lo, hi = wilson(k, n)
    return f"{k / n:.2f} [{lo:.2f}, {hi:.2f}]"


def _top_label(record: dict | None, key: str) -> str:
    """The most frequent label of `key` (strategies, failure_modes) and its share, or '–'."""
    labels = (record or {}).get(key) or {}
    if not labels or max(labels.values()) == 0.0:
        return "–"
    name = max(labels, key=labels.get)
    return f"{name} {labels[name]:.2f}"


def success_table(cells: dict) -> str:
    """Success per kind x category under each mode (Wilson 95 %), the partial openings and the
    most frequent strategy and failure mode in high ('–' for cells evaluated before the failure
    modes existed, or with no failure)."""
    lines = [
        "| kind | category | " + " | ".join(f"{m} S [95 %]" for m in MODES)
        + " | partial (high) | strategy (high) | failure mode (high) |",
        "|---|---|" + "---|" * (len(MODES) + 3),
    ]  # fmt: skip
    for kind in KINDS:
        for category in CATEGORIES:
            row = [cells.get((kind, category, m)) for m in MODES]
            if not any(row):
                continue
            high = row[-1]
            partial = f"{high['partial']:.2f}" if high else "–"
            lines.append(
                f"| {kind} | {category} | " + " | ".join(_rate(r) for r in row)
                + f" | {partial} | {_top_label(high, 'strategies')}"
                + f" | {_top_label(high, 'failure_modes')} |"
            )  # fmt: skip
    return "\n".join(lines) + "\n"


def difference_markdown(cells: dict, other: dict, names=("CoACD", "hull")) -> str:
    """Both successes and their difference (Newcombe 95 %) per kind x category in each mode."""
    a, b = names
    lines = [
        f"{a} − {b}, success difference per cell with Newcombe's 95 % interval:",
        "",
        "| kind | category | " + " | ".join(f"{m}: {a} / {b}, diff" for m in MODES) + " |",
        "|---|---|" + "---|" * len(MODES),
    ]
    for kind in KINDS:
        for category in CATEGORIES:
            values = []
            for mode in MODES:
                x, y = cells.get((kind, category, mode)), other.get((kind, category, mode))
                if x is None or y is None:
                    values.append("–")
                    continue
                (k1, n1), (k2, n2) = _count(x), _count(y)
                lo, hi = diff_interval(k1, n1, k2, n2)
                mark = "" if significant(k1, n1, k2, n2) else " (n.s.)"
                values.append(
                    f"{k1 / n1:.2f} / {k2 / n2:.2f}, {k1 / n1 - k2 / n2:+.2f} "
                    f"[{lo:+.2f}, {hi:+.2f}]{mark}"
                )
            if any(v != "–" for v in values):
                lines.append(f"| {kind} | {category} | " + " | ".join(values) + " |")
    return "\n".join(lines) + "\n"


def pooled(cells: dict, mode: str, kind: str | None = None) -> tuple[int, int]:
    """Successes and episodes over every cell of one mode (of one base kind if given)."""
    counts = [_count(r) for (k, _, m), r in cells.items() if m == mode and kind in (None, k)]
    return sum(k for k, _ in counts), sum(n for _, n in counts)
