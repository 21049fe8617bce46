#!/usr/bin/env bash
# Finger pulls from smooth to high: hook_oracle on the held-out finger pulls in the kitchen, each
# kind under each resistance mode (franka_hand, elliptic), beside the paper's human teleoperator
# (its Table 2, finger-pull handles: success 1.00, 0.96, 0.35). Writes
# experiments/kitchen/results/finger_pull_curve.md.
# Usage: bash experiments/kitchen/finger_pull_curve.sh [EPISODES]   (default 50 a cell)
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
OUT=experiments/kitchen/results/finger_pull_curve.md
TMP="$(mktemp)"
trap 'rm -f "$TMP"' EXIT
{
  echo "# Finger pulls from smooth to high: hook_oracle beside the paper's teleoperator"
  echo
  echo "Command: \`bash experiments/kitchen/finger_pull_curve.sh $EPISODES\` ($EPISODES episodes a cell over the"
  echo "test finger pulls on bases of the kind, kitchen, randomized poses, \`env.seed=0\`, CoACD,"
  echo "\`franka_hand\`/elliptic). Fail / Partial / Success; success with its Wilson 95 % interval; the"
  echo "paper's human teleoperator (its Table 2, finger-pull handles) in the last row."
  echo
  echo "| policy | kind | smooth F / P / S | normal F / P / S | high F / P / S |"
  echo "|---|---|---|---|---|"
} > "$TMP"
for kind in drawer door flap; do
  row="| hook_oracle | $kind |"
  for mode in smooth normal high; do
    line=$(realikea eval policy=hook_oracle asset=finger_pull asset.kind="$kind" asset.split=test \
      resistance="$mode" dr=randomized episodes="$EPISODES" scene=kitchen 2>/dev/null | tail -1)
    cell=$(python - "$line" <<'PY'
import json, sys
from realikea.eval.stats import wilson
line = json.loads(sys.argv[1])
n = line["episodes"]
lo, hi = wilson(round(line["success"] * n), n)
print(f"{line['fail']:.2f} / {line['partial']:.2f} / {line['success']:.2f} [{lo:.2f}, {hi:.2f}]")
PY
)
    row="$row $cell |"
  done
  echo "$row" >> "$TMP"
done
echo "| human teleoperator (paper) | – | 0.00 / 0.00 / 1.00 | 0.00 / 0.04 / 0.96 | 0.00 / 0.65 / 0.35 |" >> "$TMP"
mv "$TMP" "$OUT"
trap - EXIT
cat "$OUT"
