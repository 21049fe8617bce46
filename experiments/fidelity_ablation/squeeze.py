"""Does a trained policy's own squeeze hold it back? Evaluate a kept run's checkpoint twice on
its evaluation's draw (parts, poses, seed) in one resistance mode: as trained, and with every
closing gripper command driven to fully closed, so the Franka drive squeezes with its full
grasp force whenever the policy asks to close at all; and a scripted grasp (`grasp_sampler`, a
full-force pinch) on the same draw for reference.

    python experiments/fidelity_ablation/squeeze.py RUN [--resistance high] [--episodes 50]

The drive (realikea/conf/gripper/franka_hand.yaml) pushes towards the commanded opening with at
most grasp_force per jaw, reaching it only 2 mm (`saturation`) short of the target: a policy
whose command sits within 2 mm of the part's width squeezes with less. Prints success with
Wilson's 95 % interval, full squeeze − as trained with Newcombe's, the mean squeeze while
pulling (`grip_force`) and the failure modes, and writes the table to --out.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from realikea.errors import RealIkeaError
from realikea.eval.setup import eval_setup, evaluate
from realikea.eval.stats import count, diff_interval, significant, wilson
from realikea.eval.table import cell_row
from realikea.files import atomic_write_text, shown_path
from realikea.markdown import table
from realikea.policies.full_squeeze import FullSqueeze
from realikea.runs.records import mode_overrides


def squeeze_table(rows: dict[str, dict]) -> list[str]:
    """Markdown: each variant's outcome, squeeze and failure modes; the difference."""
    header = ["variant", "success [95 %]", "partial", "grip_force (N)", "peak_pull (N)", "slip",
              "interference", "clearance"]  # fmt: skip
    cells = []
    for name, (row, summary) in rows.items():
        n = row["episodes"]
        k = count(row["success"], n)
        low, high = wilson(k, n)
        modes = summary.get("failure_modes", {})
        cells.append([
            name, f"{k / n:.2f} [{low:.2f}, {high:.2f}]", f"{row['partial']:.2f}",
            f"{row['grip_force']:.1f}", f"{row['peak_pull']:.1f}", f"{modes.get('slip', 0):.2f}",
            f"{modes.get('mutual_interference', 0):.2f}", f"{modes.get('narrow_clearance', 0):.2f}",
        ])  # fmt: skip
    out = table(header, "llrrrrrr", cells)
    (trained, _), (squeezed, _) = list(rows.values())[:2]
    n = trained["episodes"]
    ks, kt = count(squeezed["success"], n), count(trained["success"], n)
    low, high = diff_interval(ks, n, kt, n)
    verdict = "significant" if significant(ks, n, kt, n) else "not significant"
    out += ["", f"full squeeze − as trained: {(ks - kt) / n:+.2f} [{low:+.2f}, {high:+.2f}], "
            f"{verdict}"]  # fmt: skip
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run", type=Path, help="a kept run (with eval.json and its checkpoint)")
    parser.add_argument("--resistance", default="high")
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--scripted", default="grasp_sampler", help="the reference policy")
    parser.add_argument("--out", type=Path, help="markdown file (default: RUN/squeeze.md)")
    args = parser.parse_args()
    try:
        overrides = mode_overrides(args.run, args.resistance, args.episodes)
    except RealIkeaError as err:
        parser.error(str(err))
    scripted = [t for t in overrides if not t.startswith("policy")] + [f"policy={args.scripted}"]
    variants = {
        "as trained": (overrides, lambda p: p),
        "full squeeze": (overrides, FullSqueeze),
        f"{args.scripted} (scripted)": (scripted, lambda p: p),
    }
    rows, notes = {}, []
    for name, (variant_overrides, wrap) in variants.items():
        cfg, policy = eval_setup(variant_overrides)
        wrapped = wrap(policy)
        result = evaluate(cfg, wrapped)
        category = str(cfg.asset.category)
        rows[name] = (cell_row(cfg, name, category, args.resistance, result), result.summary())
        if wrap is FullSqueeze:
            closing = np.asarray(wrapped.closing)
            notes.append(
                f"The policy's own closing commands (gripper action < 0): {len(closing)}, "
                f"median {np.median(closing):+.2f}; {np.mean(closing > -0.9):.2f} of them "
                "above −0.9 (a target opening of 2 mm or more per finger: less than the full "
                "force on a part narrower than that)."
            )
    lines = [
        f"# Squeeze of {shown_path(args.run.resolve())}, {args.resistance}",
        "",
        f"`realikea eval {' '.join(overrides)}`, as trained and with every closing gripper "
        "command at fully closed "
        f"(`python experiments/fidelity_ablation/squeeze.py {shown_path(args.run.resolve())} "
        f"--resistance {args.resistance} --episodes {args.episodes}`).",
        "",
        *squeeze_table(rows),
        "",
        *notes,
    ]
    print("\n".join(lines))
    atomic_write_text(args.out or args.run / "squeeze.md", "\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
