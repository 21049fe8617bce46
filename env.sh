# Source me (`. ./env.sh`): activates the project's .venv when setup.sh made one (an externally
# managed Python, PEP 668); without one, the current Python is the project's and nothing changes.
if [ -f "$(dirname "${BASH_SOURCE[0]:-$0}")/.venv/bin/activate" ]; then
  . "$(dirname "${BASH_SOURCE[0]:-$0}")/.venv/bin/activate"
fi
