#!/usr/bin/env bash
# What the sealed hull leaves of a finger-pull door: the three scripted policies (heuristic pull,
# grasp sampler, hook oracle) on the test finger pulls, doors, high resistance, kitchen,
# franka_hand / elliptic, hull collision, 50 randomized episodes a policy. The same cells on
# CoACD are Table 2's (experiments/table2/results/door/franka_hand_elliptic/).
# Usage: bash experiments/generalist/hull_fp_doors.sh [EPISODES]   (about 10 min alone)
set -euo pipefail
cd "$(dirname "$0")/../.."
realikea eval table table.kind=door collision=hull "table.categories=[finger_pull]" \
  "table.resistances=[high]" scene=kitchen asset.split=test episodes="${1:-50}" \
  table.out=experiments/generalist/results/hull_fp_doors_scripted
