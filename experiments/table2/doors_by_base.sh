#!/usr/bin/env bash
# Why doors stop at 0.74 in Table 2: heuristic_pull on the test two-point handles, smooth
# resistance (nothing slips), kitchen, franka_hand / elliptic, per door base: success and partial
# openings. Writes experiments/table2/results/doors_by_base.md.
# Usage: bash experiments/table2/doors_by_base.sh [EPISODES]   (default 20 per base)
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-20}"
OUT=experiments/table2/results/doors_by_base.md
{
  echo "# Doors by base (\`bash experiments/table2/doors_by_base.sh $EPISODES\`)"
  echo
  echo "heuristic_pull, two-point test parts, smooth, kitchen, franka_hand / elliptic, randomized"
  echo "poses, $EPISODES episodes per base."
  echo
  echo "| base | success | partial | fail |"
  echo "|---|---:|---:|---:|"
  for base in door_left_w40_h80 door_left_w60_h80 door_right_w40_h80 door_right_w60_h80; do
    line=$(realikea eval policy=heuristic_pull asset=two_point asset.base="$base" asset.split=test \
      resistance=smooth dr=randomized scene=kitchen episodes="$EPISODES" 2>/dev/null | tail -1)
    python -c "import json,sys; d=json.loads(sys.argv[2]); print(f\"| {sys.argv[1]} | {d['success']:.2f} | {d['partial']:.2f} | {d['fail']:.2f} |\")" "$base" "$line"
  done
} > "$OUT"
cat "$OUT"
