#!/usr/bin/env bash
# Install everything Real-IKEA needs on a fresh Debian/Ubuntu machine: Mesa's OSMesa for offscreen
# MuJoCo rendering on the CPU, then this package with its Python dependencies (editable).
# Python: the active environment (a venv, conda, pyenv, or a system Python that lets pip install),
# else, when the interpreter is externally managed (PEP 668: Debian 12, Ubuntu 24.04), a project
# virtual environment in .venv; `. ./env.sh` activates it (and does nothing without one).
set -euo pipefail
cd "$(dirname "$0")"
SUDO=$([ "$(id -u)" -eq 0 ] && echo "" || echo "sudo")
apt_install() {
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "$@" >/dev/null
}
if ! ldconfig -p | grep -q libOSMesa; then
  apt_install libosmesa6
fi
PYTHON=python3
if [ -z "${VIRTUAL_ENV:-}" ] && python3 - <<'PY'
import sys, sysconfig
from pathlib import Path
sys.exit(0 if (Path(sysconfig.get_path("stdlib")) / "EXTERNALLY-MANAGED").is_file() else 1)
PY
then
  if [ ! -x .venv/bin/python ]; then
    python3 -c "import ensurepip" 2>/dev/null || apt_install python3-venv
    python3 -m venv .venv
  fi
  PYTHON=.venv/bin/python
  echo "this Python is externally managed (PEP 668): installing into .venv; activate it with . ./env.sh"
fi
"$PYTHON" -m pip install -q --disable-pip-version-check -e '.[dev]'
