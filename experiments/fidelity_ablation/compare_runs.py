"""Two finished runs side by side: each one's success per evaluation mode with Wilson's 95 %
interval, and A − B with Newcombe's, "not significant" where that interval includes zero (e.g.
one seed at two schedules, which the report does not pool).

    python experiments/fidelity_ablation/compare_runs.py RUN_A RUN_B
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from fidelity_report.compare import comparison_lines

from realikea.errors import RealIkeaError


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_a", type=Path)
    parser.add_argument("run_b", type=Path)
    args = parser.parse_args(argv)
    try:
        print("\n".join(comparison_lines(args.run_a, args.run_b)))
    except RealIkeaError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
