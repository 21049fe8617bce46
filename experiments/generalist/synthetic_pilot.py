"""The pilot before a round 25: does a two-point flap teacher trained with synthetic parts past
each family's sizes open the family's smallest train part, withheld from its training?
(registered in README.md, "A pilot: parts beyond a family's sizes").

    python experiments/generalist/synthetic_pilot.py            # resumable: training, then reads
    python experiments/generalist/synthetic_pilot.py --dry-run
    python experiments/generalist/synthetic_pilot.py --park      # stopped runs' state into git

Four runs, two at a time (the run queue: realikea/training/queue.py), in
outputs/generalist_synthetic_pilot/NAME, kept in results/synthetic_pilot/NAME with their learning
curves: arm A (`withheld`: the kind teachers' recipe on the two-point flaps, less the validation
parts) and arm B (`synthetic`: the same and synthetic parts, `asset.synthetic`) on seeds 30 and 31.
Each kept run's last checkpoint, its mean action, is read on the validation draw (train parts'
poses, `env.seed=VALIDATION_SEED`, randomized) in normal and high resistance: on each validation
part (10 episodes a part, so 50 over the five) and on the parts it trained on (50 episodes), one
JSON line a read in RUN/pilot_cells.jsonl. Then the table and the go rule, printed and written
to results/synthetic_pilot/pilot.md.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from kept_queue import driver_arguments, kept_queue

from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.sweep import VALIDATION_SEED, checkpoints
from realikea.files import WORKSPACE, atomic_write_text, shown_path
from realikea.markdown import table
from realikea.training.queue import QueuedRun

HERE = Path(__file__).resolve().parent
KEPT = HERE / "results/synthetic_pilot"
PARKED = HERE / "results/synthetic_pilot_parked"
WORK = WORKSPACE / "outputs/generalist_synthetic_pilot"
# each two-point family's smallest train part (realikea/catalog/parts.csv, split.csv)
VALIDATION_PARTS = (
    "tp_round_bar_64", "tp_flat_bar_96", "tp_d_handle_96", "tp_u_handle_96", "tp_bow_128",
)  # fmt: skip
WITHHOLD = f"asset.withhold=[{','.join(VALIDATION_PARTS)}]"
SYNTHETIC = "asset.synthetic={span: [0.667, 1.5], per_family: 4}"
CELL = ("asset=two_point", "asset.kind=flap")
# the kind teachers' recipe (realikea/conf/pipeline/distilled.yaml: every_stage and teacher)
TEACHER = ("agent=ppo", "asset.rotate_every=10", "agent.max_iterations=400",
           "dr.switch_iteration=200", "logger=none")  # fmt: skip
ITERATIONS = 400
ARMS = {"withheld": (WITHHOLD,), "synthetic": (WITHHOLD, SYNTHETIC)}
SEEDS = (30, 31)
MODES = ("normal", "high")
EPISODES_A_PART, EPISODES_TRAINED = 10, 50
# the go rule: the validation parts up at least GO_GAIN, the trained parts down at most GO_COST
GO_GAIN, GO_COST = 0.10, 0.05


def runs() -> list[QueuedRun]:
    return [
        QueuedRun(f"{arm}_s{seed}", (*CELL, *TEACHER, *extra, f"env.seed={seed}"), ITERATIONS)
        for seed in SEEDS
        for arm, extra in ARMS.items()
    ]


def reads() -> list[tuple[str, str, tuple[str, ...], int]]:
    """(what, mode, cell overrides, episodes) of every read of a run."""
    parts = [(part, (f"asset.part={part}",), EPISODES_A_PART) for part in VALIDATION_PARTS]
    trained = [("trained", ("asset.split=train", WITHHOLD), EPISODES_TRAINED)]
    return [(what, mode, cell, n) for what, cell, n in parts + trained for mode in MODES]


def read_run(run: Path) -> list[dict]:
    """The run's reads, made where missing (appended to RUN/pilot_cells.jsonl one at a time)."""
    path = run / "pilot_cells.jsonl"
    done = [json.loads(line) for line in path.open()] if path.is_file() else []
    checkpoint = checkpoints(run)[-1][1]
    for what, mode, cell, episodes in reads():
        if any(r["what"] == what and r["resistance"] == mode for r in done):
            continue
        overrides = [
            "policy=checkpoint", f"policy.path={shown_path(checkpoint)}", *CELL, *cell,
            f"resistance={mode}", "dr=randomized", f"episodes={episodes}",
            f"env.seed={VALIDATION_SEED}",
        ]  # fmt: skip
        cfg, policy = eval_setup(overrides)
        summary = evaluate(cfg, policy, progress=False).summary()
        command = "realikea eval " + " ".join(overrides)
        done.append({"what": what, "resistance": mode, "episodes": episodes,
                     "success": summary["success"], "command": command})  # fmt: skip
        atomic_write_text(path, "".join(json.dumps(r) + "\n" for r in done))
        print(f"{run.name}: {what} {mode} {summary['success']:.2f}", flush=True)
    return done


def rates(done: list[dict]) -> dict[tuple[str, str], float]:
    """(validation|trained, mode) -> success: the validation parts' episodes pooled."""
    out = {}
    for mode in MODES:
        parts = [r for r in done if r["resistance"] == mode and r["what"] in VALIDATION_PARTS]
        won = sum(r["success"] * r["episodes"] for r in parts)
        out["validation", mode] = won / sum(r["episodes"] for r in parts)
        out["trained", mode] = next(
            r["success"] for r in done if r["resistance"] == mode and r["what"] == "trained"
        )
    return out


def report(read: dict[str, dict]) -> str:
    """The pilot's table and its go rule's verdict, as markdown."""
    rows, passes = [], []
    for seed in SEEDS:
        a, b = read[f"withheld_s{seed}"], read[f"synthetic_s{seed}"]
        for mode in MODES:
            gain = round(b["validation", mode] - a["validation", mode], 6)
            cost = round(a["trained", mode] - b["trained", mode], 6)
            passes.append(gain >= GO_GAIN and cost <= GO_COST)
            cells = [
                a["validation", mode],
                b["validation", mode],
                a["trained", mode],
                b["trained", mode],
            ]
            v_a, v_b, t_a, t_b = (f"{x:.2f}" for x in cells)
            gained, lost = f"{gain + 0.0:+.2f}", f"{0.0 - cost:+.2f}"  # no "-0.00"
            rows.append((str(seed), mode, v_a, v_b, gained, t_a, t_b, lost))
    verdict = "go: yes" if all(passes) else "go: no"
    return "\n".join([
        "# The synthetic-parts pilot: two-point flap teachers, validation draw",
        "",
        f"`python experiments/generalist/synthetic_pilot.py`; each run's last checkpoint, mean "
        f"action, `env.seed={VALIDATION_SEED}`, randomized poses; validation parts "
        f"{', '.join(VALIDATION_PARTS)} ({EPISODES_A_PART} episodes a part), trained parts "
        f"{EPISODES_TRAINED} episodes. Rule: on both seeds and modes, B - A on the validation "
        f"parts >= {GO_GAIN:.2f} and on the trained parts >= -{GO_COST:.2f}.",
        "",
        *table(("seed", "mode", "A: validation parts", "B: validation parts", "B - A",
                "A: trained parts", "B: trained parts", "B - A"), "llrrrrrr", rows),  # fmt: skip
        "",
        f"**{verdict}** ({sum(passes)} of {len(passes)} seed x mode pairs pass)",
        "",
    ])  # fmt: skip


def main(argv: list[str]) -> int:
    args = driver_arguments(__doc__, argv)
    queue = kept_queue(WORK, KEPT, PARKED)
    status = queue.serve(runs(), 2, dry_run=args.dry_run, park=args.park)
    if status or args.dry_run or args.park or not all(queue.kept(r) for r in runs()):
        return status
    read = {run.name: rates(read_run(KEPT / run.name)) for run in runs()}
    text = report(read)
    atomic_write_text(KEPT / "pilot.md", text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
