#!/usr/bin/env bash
# The committed checkpoints that opened through a front's free edge (the hull finger-pull policy,
# the CoACD knob policy; both trained freestanding on drawers in high resistance) evaluated on the
# held-out test parts, freestanding and in the kitchen scene. Writes experiments/kitchen/results/reeval.md.
# Usage: bash experiments/kitchen/reeval.sh [EPISODES]
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
OUT=experiments/kitchen/results/reeval.md
TMP="$(mktemp)"
trap 'rm -f "$TMP"' EXIT
{
  echo "# Shortcut policies in the kitchen"
  echo
  echo "Command: \`bash experiments/kitchen/reeval.sh $EPISODES\` ($EPISODES episodes a row, test parts,"
  echo "drawers, high resistance, randomized poses, draw \`env.seed=1000\`, franka_hand / elliptic)."
  echo "Intervals: Wilson 95 %."
  echo
  echo "| run | scene | success | front_pinch + front_hook | hook | lever | pinch | none |"
  echo "|---|---|---|---:|---:|---:|---:|---:|"
} > "$TMP"
for run in hull_high_finger_pull_franka_hand_s0 coacd_high_knob_franka_hand_s0; do
  collision="${run%%_*}"
  category=$(echo "$run" | sed -E 's/^[a-z]+_high_(.*)_franka_hand_s0$/\1/')
  for scene in freestanding kitchen; do
    # the kitchen as these rows were measured in: every arm 0.80 m below its handle
    placed=(); [ "$scene" = kitchen ] && placed=("scene.robot.placements=[]")
    line=$(realikea eval policy=checkpoint \
      policy.path="experiments/fidelity_ablation/results/runs/$run/model_499.pt" \
      asset="$category" asset.kind=drawer asset.split=test collision="$collision" \
      resistance=high dr=randomized env.seed=1000 episodes="$EPISODES" scene="$scene" \
      "${placed[@]}" 2>/dev/null | tail -1)
    python - "$run" "$scene" "$line" >> "$TMP" <<'PY'
import json, sys
from realikea.eval.stats import wilson
run, scene, line = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
n, s = line["episodes"], line["strategies"]
k = round(line["success"] * n)
lo, hi = wilson(k, n)
front = s["front_pinch"] + s["front_hook"]
print(f"| {run} | {scene} | {line['success']:.2f} [{lo:.2f}, {hi:.2f}] | {front:.2f} | "
      f"{s['hook']:.2f} | {s['lever']:.2f} | {s['pinch']:.2f} | {s['none']:.2f} |")
PY
  done
done
mv "$TMP" "$OUT"
trap - EXIT
cat "$OUT"
