#!/usr/bin/env bash
# The paper's Table 2 in the kitchen scene on the held-out test parts, on drawers and on doors,
# under every gripper x contact preset; then the grip-force sensitivity run and the report.
# Usage: bash experiments/table2/run.sh [EPISODES]   (default 50 episodes per cell)
# Each kind x preset writes experiments/table2/results/<kind>/<gripper>_<contact>/table2.{csv,md};
# report.py writes experiments/table2/results/report.md and success.png from them; wall times go to
# experiments/table2/results/timing.txt.
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
HERE=experiments/table2
OUT=$HERE/results
COMMON=(scene=kitchen asset.split=test episodes="$EPISODES")
: > "$OUT/timing.txt"
for kind in drawer door; do
  for gripper in franka_hand menagerie_servo; do
    for contact in elliptic pyramidal; do
      echo "=== kind=$kind gripper=$gripper contact=$contact"
      start=$SECONDS
      realikea eval table gripper="$gripper" contact="$contact" table.kind="$kind" "${COMMON[@]}" \
        table.out="$OUT/$kind/${gripper}_${contact}"
      echo "$kind $gripper $contact: $((SECONDS - start)) s" >> "$OUT/timing.txt"
    done
  done
done
# sensitivity of the friction-based pull to the grip force, on drawers (not a calibration: see
# experiments/table2/README.md)
for force in 5 10 20; do
  start=$SECONDS
  realikea eval table gripper=franka_hand contact=elliptic gripper.grasp_force="$force" \
    "table.policies=[heuristic_pull]" "table.categories=[knob,finger_pull]" table.kind=drawer \
    "${COMMON[@]}" table.out="$OUT/grip_sweep/franka_hand_elliptic_${force}N"
  echo "grip sweep drawer ${force} N: $((SECONDS - start)) s" >> "$OUT/timing.txt"
done
python "$HERE/report.py"
