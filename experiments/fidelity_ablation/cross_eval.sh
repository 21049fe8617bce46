#!/usr/bin/env bash
# Robustness of the learned strategies: the two-point policies trained with franka_hand
# (elliptic, high resistance; CoACD vs hull) evaluated in high resistance with a drive or cone
# under which friction can slip, one pair per training seed. Writes
# experiments/fidelity_ablation/results/cross_eval.md.
# Usage: bash experiments/fidelity_ablation/cross_eval.sh [EPISODES] [SEEDS]   (SEEDS: "0 2 3")
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
SEEDS="${2:-0}"
OUT=experiments/fidelity_ablation/results/cross_eval.md
TMP="$(mktemp)"
trap 'rm -f "$TMP"' EXIT
{
  echo "# Learned strategies under a slipping grasp (two-point drawers, high resistance)"
  echo
  echo "Command: \`bash experiments/fidelity_ablation/cross_eval.sh\` ($EPISODES episodes a row,"
  echo "randomized poses, held-out draw \`env.seed=1000\` over all parts, freestanding scene as"
  echo "the runs were trained). Both policies were trained with"
  echo "\`franka_hand\` and elliptic cones in high resistance"
  echo "(runs/*_high_two_point_franka_hand_s<seed>, seeds $SEEDS); each is evaluated with its own"
  echo "collision source."
  echo
  echo "| trained with | seed | evaluated with | fail | partial | success | hook | pinch | none |"
  echo "|---|---:|---|---:|---:|---:|---:|---:|---:|"
} > "$TMP"
for seed in $SEEDS; do
  for collision in coacd hull; do
    for preset in "contact=elliptic" "contact=pyramidal" "gripper.grasp_force=10" "gripper=menagerie_servo"; do
      line=$(realikea eval policy=checkpoint \
        policy.path="experiments/fidelity_ablation/results/runs/${collision}_high_two_point_franka_hand_s${seed}/model_499.pt" \
        asset=two_point asset.kind=drawer asset.split=all scene=freestanding \
        collision="$collision" resistance=high dr=randomized env.seed=1000 episodes="$EPISODES" $preset 2>/dev/null | tail -1)
      python - "$collision" "$seed" "$preset" "$line" >> "$TMP" <<'PY'
import json, sys
collision, seed, preset, line = *sys.argv[1:4], json.loads(sys.argv[4])
s = line["strategies"]
print(f"| {collision} | {seed} | {preset} | {line['fail']:.2f} | {line['partial']:.2f} | "
      f"{line['success']:.2f} | {s['hook']:.2f} | {s['pinch']:.2f} | {s['none']:.2f} |")
PY
    done
  done
done
mv "$TMP" "$OUT"
trap - EXIT
cat "$OUT"
