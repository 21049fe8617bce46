"""One checkpoint over the library's grid, kind x category x resistance mode, on the held-out parts
(or, with `split="train"` and the validation seed, on the validation draw).

`evaluate_grid` runs `realikea eval` (its own setup: the checkpoint's run groups, the strategy
classifier) once per cell and appends the cell's JSON line (outcomes, labels, and the contact
statistics of its episodes that pulled: `contact_record`) to a results file as it goes, so an
interrupted grid continues where it stopped; `read_cells` reads such a file back, `cell_count`
and `pooled` count its successes.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

from realikea.assets.catalog import BASE_KINDS, CATEGORIES, effective_split
from realikea.eval.runs import contact_record, run_scene
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.stats import count
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
    split: str = "test",
) -> list[str]:
    """`realikea eval` overrides of one cell: the split's parts (test: held out), randomized
    poses, the draw's seed, in the scene the checkpoint's run was trained in (`run_scene`, when
    its `.hydra` sits beside it: a placement changed since does not move its arm)."""
    hydra = Path(checkpoint).parent / ".hydra"
    scene = run_scene(hydra) if (hydra / "config.yaml").is_file() else []
    return [
        "policy=checkpoint", f"policy.path={shown_path(Path(checkpoint).resolve())}",
        f"asset={category}", f"asset.kind={kind}", f"resistance={mode}", f"asset.split={split}",
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
    split: str = "test",
) -> dict[tuple[str, str, str], dict]:
    """Evaluate every cell missing from `results`, appending one JSON line per cell."""
    results = Path(results)
    results.parent.mkdir(parents=True, exist_ok=True)
    done = read_cells(results)
    todo = [(k, c, m) for k in kinds for c in categories for m in modes if (k, c, m) not in done]
    for n, (kind, category, mode) in enumerate(todo, 1):
        overrides = cell_overrides(
            checkpoint, kind, category, mode, episodes, seed, extra or [], split
        )
        start = time.perf_counter()
        cfg, policy = eval_setup(overrides)
        result = evaluate(cfg, policy, progress=False)
        summary = result.summary()
        record = {
            "kind": kind, "category": category, "resistance": mode,
            "collision": str(cfg.collision.source), "scene": str(cfg.scene.name),
            "split": effective_split(cfg.asset), "seed": seed, **summary,
            **contact_record(result.episodes),
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


def cell_count(record: dict) -> tuple[int, int]:
    """Successes and episodes of a cell (its success rate is k / n of its episodes)."""
    n = int(record["episodes"])
    return count(record["success"], n), n


def pooled(cells: dict, mode: str, kind: str | None = None) -> tuple[int, int]:
    """Successes and episodes over every cell of one mode (of one base kind if given)."""
    counts = [cell_count(r) for (k, _, m), r in cells.items() if m == mode and kind in (None, k)]
    return sum(k for k, _ in counts), sum(n for _, n in counts)
