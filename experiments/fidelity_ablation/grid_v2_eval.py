"""The fidelity grid v2's evaluations beyond each run's own eval.json (CoACD geometry, written when
the run finished): hull runs on their own hull, the hard-pad phase map of the two-point x high
policies (registered comparison 4), and frames of each strategy label a policy shows. Resumable:
what is done is skipped.

    python experiments/fidelity_ablation/grid_v2_eval.py            # both, for every kept run
    python experiments/fidelity_ablation/grid_v2_eval.py --dry-run  # what would run

Own geometry: `realikea eval rerun --collision hull RUN` (its train.eval_after on the hull: test
parts, smooth/normal/high, 50 episodes a mode, randomized poses, draw 1000) into
RUN/eval_hull.json. Phase map: every kept two-point x high policy in high at pad friction
PHASE_FRICTION and grip forces PHASE_FORCES per jaw, the recipe's elliptic cones, 50 episodes a
cell on the same draw, the recipe composed (the grid's scene and placements), one JSON line a
cell in results/grid_v2/phase_map/cells.jsonl, labelled by run name. Frames: VIDEO_EPISODES
episodes of the run's evaluation under its training resistance, the first of each strategy label
as a four-frame strip (committed) and an MP4 (git-ignored) in RUN/videos/, to look at before a
strategy is credited.
"""

from __future__ import annotations

import argparse
import sys

from fidelity_report.videos import record_videos
from grid_v2 import KEPT, RECIPE_OVERRIDES

from realikea.errors import RealIkeaError
from realikea.eval.runs import rerun
from realikea.reports.phase_map import evaluate_phase_map, map_policy
from realikea.runs.records import find_runs

OWN = "hull"  # the runs whose own geometry is not the protocol's
OWN_FILE = f"eval_{OWN}.json"
PHASE_CELL = ("two_point", "high")  # (category, training resistance) of the mapped policies
PHASE_FRICTION, PHASE_FORCES, PHASE_CONE = 0.3, (40.0, 70.0), "elliptic"  # the hard pad
PHASE_EPISODES, PHASE_SEED = 50, 1000
PHASE_RESULTS = KEPT / "phase_map" / "cells.jsonl"
VIDEO_EPISODES = 8


def kept_runs() -> list:
    """Kept grid runs (a finished run holds eval.json), by name."""
    return sorted(p.parent for p in KEPT.glob("*/eval.json"))


def kept_records(kept=KEPT) -> list[dict]:
    """`find_runs`'s record of each kept grid run (not the pilot's, in a subfolder)."""
    return [r for r in find_runs([kept]) if r["dir"].parent == kept]


def own_geometry_todo(runs) -> list:
    return [r for r in runs if r.name.startswith(f"{OWN}_") and not (r / OWN_FILE).is_file()]


def phase_policies(runs) -> list[str]:
    """LABEL=CHECKPOINT of every kept policy of the mapped cell (its last, slim checkpoint)."""
    category, resistance = PHASE_CELL
    chosen = [r for r in runs if f"_{resistance}_{category}_s" in r.name]
    return [f"{r.name}={max(r.glob('model_*.pt'))}" for r in chosen]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dry-run", action="store_true", help="list what would run")
    args = parser.parse_args()
    runs = kept_runs()
    todo, mapped = own_geometry_todo(runs), phase_policies(runs)
    print(f"{len(runs)} kept runs; {len(todo)} to evaluate on the {OWN}; {len(mapped)} mapped")
    if args.dry_run:
        for line in [*(f"own: {r.name}" for r in todo), *(f"map: {m}" for m in mapped)]:
            print(line)
        return 0
    try:
        if todo:
            rerun(todo, OWN)
        evaluate_phase_map(
            [map_policy(m) for m in mapped], [PHASE_CELL[0]], PHASE_RESULTS, PHASE_FORCES,
            [PHASE_FRICTION], [PHASE_CONE], PHASE_EPISODES, PHASE_SEED, RECIPE_OVERRIDES,
        )  # fmt: skip
        record_videos(kept_records(), VIDEO_EPISODES)
    except RealIkeaError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
