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
    /usr/bin/time -f "preset wall time: %e s" \
      realikea eval table gripper="$gripper" contact="$contact" episodes="$EPISODES"
  done
done
python experiments/table2/report.py
