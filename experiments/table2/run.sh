#!/usr/bin/env bash
# The paper's Table 2 under every gripper x contact preset, then the cross-preset report.
# Usage: bash experiments/table2/run.sh [EPISODES]   (default 50 episodes per cell)
# Each preset writes experiments/table2/<gripper>_<contact>/table2.{csv,md};
# report.py writes experiments/table2/report.md and success.png from them.
set -euo pipefail
cd "$(dirname "$0")/../.."
EPISODES="${1:-50}"
for gripper in franka_hand menagerie_servo; do
  for contact in elliptic pyramidal; do
    echo "=== gripper=$gripper contact=$contact"
    start=$SECONDS
    realikea eval table gripper="$gripper" contact="$contact" episodes="$EPISODES"
    echo "preset $gripper $contact seconds $((SECONDS - start))"
  done
done
# sensitivity of the friction-based pull to the grip force (not a calibration: see README.md)
for force in 5 10 20; do
  realikea eval table gripper=franka_hand contact=elliptic gripper.grasp_force="$force" \
    "table.policies=[heuristic_pull]" "table.categories=[knob,finger_pull]" episodes="$EPISODES" \
    table.out="experiments/table2/grip_sweep/franka_hand_elliptic_${force}N"
done
python experiments/table2/report.py
