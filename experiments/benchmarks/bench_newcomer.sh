#!/usr/bin/env bash
# The README's newcomer path, timed: a fresh clone of this checkout set up with the stock
# interpreter (Debian/Ubuntu's externally managed /usr/bin/python3, so setup.sh makes .venv),
# then the quick start's steps one by one. The library that set-up's first command builds
# (`realikea assets build --all`, about 20 min) is hard-linked from this checkout's build instead.
# Usage: bash experiments/benchmarks/bench_newcomer.sh [CLONE_DIR]   (default /tmp/realikea_newcomer)
# Each step's output: CLONE_DIR.<step>.log; the timings on stdout.
set -uo pipefail
SOURCE="$(cd "$(dirname "$0")/../.." && pwd)"
CLONE="${1:-/tmp/realikea_newcomer}"
export PATH="/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin"  # Debian's own
rm -rf "$CLONE" && git clone -q "$SOURCE" "$CLONE" && cd "$CLONE" || exit 1
step() {
  local name="$1" start end
  shift
  start=$(date +%s.%N)
  "$@" >"$CLONE.$name.log" 2>&1
  local rc=$?
  end=$(date +%s.%N)
  printf '%-8s exit %s  %6.1f s\n' "$name" "$rc" "$(echo "$end - $start" | bc)"
}
echo "interpreter: $(command -v python3), $(python3 --version)"
step setup bash setup.sh
. ./env.sh
echo "environment: $(python3 -c 'import sys; print(sys.prefix)')"
mkdir -p outputs && cp -al "$SOURCE/.cache" . && cp -al "$SOURCE/outputs/assets" outputs/
step build realikea assets build --part tp_round_bar_128 --base drawer_w60_h20
step train python3 train.py asset=two_point asset.kind=drawer agent.max_iterations=100 logger=none hydra.run.dir=outputs/quickstart
step eval realikea eval policy=checkpoint policy.path=experiments/generalist/results/coacd/model_1499.pt asset=two_point asset.kind=flap episodes=4 video=true video_path=outputs/flap
ls outputs/flap_*.mp4
# the viewer needs a display: here only its module and the model it would open are loaded
step viewer python3 -c "import mujoco, mujoco.viewer; mujoco.MjModel.from_xml_path('outputs/assets/tp_round_bar_128__drawer_w60_h20/model_coacd.xml')"
