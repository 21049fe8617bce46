#!/usr/bin/env bash
# Read the recorded datasets back with LeRobot itself (tests/test_lerobot.py, lerobot 0.4.4), in a
# throw-away venv beside the project's Python. Not part of the default install or CI, because:
# - every lerobot release pins torch below the project's 2.13.0 (0.4.4: torch<2.11), so lerobot
#   goes in with --no-deps, over the packages its LeRobotDataset imports;
# - PyPI's torchvision is linked against CUDA torch: beside the CPU build its _C library does not
#   load, and its import then fails registering fake kernels for two ops it never defined
#   (torchvision::nms, qnms). sitecustomize.py defines their schemas first; no image op runs.
# Usage: bash experiments/lerobot_sample/readback.sh [VENV]   (default: a temporary folder)
set -euo pipefail
cd "$(dirname "$0")/../.."
VENV=${1:-$(mktemp -d)/lerobot}
python3 -m venv --system-site-packages "$VENV"
echo "torch==2.13.0" > "$VENV/constraints.txt"
"$VENV/bin/pip" install -q --disable-pip-version-check -c "$VENV/constraints.txt" \
  torchvision==0.28.0 'av>=15,<16' 'datasets>=4,<4.2' 'huggingface-hub>=0.34.2,<0.36' \
  'accelerate>=1.10,<2'
"$VENV/bin/pip" install -q --disable-pip-version-check --no-deps lerobot==0.4.4
SITE=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_path("purelib"))')
cat > "$SITE/sitecustomize.py" <<'PY'
import torch

_TORCHVISION_OPS = torch.library.Library("torchvision", "FRAGMENT")
for _op in ("nms", "qnms"):
    _TORCHVISION_OPS.define(f"{_op}(Tensor dets, Tensor scores, float iou_threshold) -> Tensor")
PY
"$VENV/bin/python" -c 'import lerobot; from importlib.metadata import version; print("lerobot", version("lerobot"))'
"$VENV/bin/python" -m pytest -q -p no:cacheprovider tests/test_lerobot.py -rs
