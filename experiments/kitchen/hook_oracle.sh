#!/usr/bin/env bash
# Form closure across the library: hook_oracle in high resistance on the held-out test parts in
# the kitchen scene, every category on every kind, under franka_hand/elliptic and
# menagerie_servo/pyramidal. Writes experiments/kitchen/results/hook_oracle.md.
# Usage: bash experiments/kitchen/hook_oracle.sh [EPISODES]
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
OUT=experiments/kitchen/results/hook_oracle.md
TMP="$(mktemp)"
trap 'rm -f "$TMP"' EXIT
{
  echo "# hook_oracle (form closure) in the kitchen, high resistance, test parts"
  echo
  echo "Command: \`bash experiments/kitchen/hook_oracle.sh $EPISODES\` ($EPISODES episodes a cell over the"
  echo "test parts of the category on bases of the kind, randomized poses, \`env.seed=0\`, CoACD)."
  echo "Success with its Wilson 95 % interval; \`no catch\`: episodes whose part offers nothing to get"
  echo "behind (the oracle plans no motion and says why; counted as failures); \`with a catch\`: success"
  echo "over the other episodes."
  echo
  echo "| preset | category | kind | success | with a catch | hook + lever of successes | no catch | fail / partial |"
  echo "|---|---|---|---|---:|---:|---:|---|"
} > "$TMP"
for preset in "gripper=franka_hand contact=elliptic" "gripper=menagerie_servo contact=pyramidal"; do
  for category in two_point finger_pull knob; do
    for kind in drawer door flap; do
      # shellcheck disable=SC2086
      line=$(realikea eval policy=hook_oracle asset="$category" asset.kind="$kind" asset.split=test \
        resistance=high dr=randomized episodes="$EPISODES" scene=kitchen $preset 2>/dev/null | tail -1)
      python - "$preset" "$category" "$kind" "$line" >> "$TMP" <<'PY'
import json, sys
from realikea.eval.stats import wilson
preset, category, kind, line = *sys.argv[1:4], json.loads(sys.argv[4])
n = line["episodes"]
k = round(line["success"] * n)
lo, hi = wilson(k, n)
no_catch = sum(line.get("policy_notes", {}).values())
caught = max(n - no_catch, 0)
with_catch = f"{k / caught:.2f}" if caught else "-"
won = line.get("success_strategies", {})
form = won.get("hook", 0.0) + won.get("lever", 0.0)
print(f"| {preset.replace('gripper=', '').replace(' contact=', ' / ')} | {category} | {kind} | "
      f"{line['success']:.2f} [{lo:.2f}, {hi:.2f}] | {with_catch} | {form:.2f} | {no_catch} | "
      f"{line['fail']:.2f} / {line['partial']:.2f} |")
PY
    done
  done
done
mv "$TMP" "$OUT"
trap - EXIT
cat "$OUT"
