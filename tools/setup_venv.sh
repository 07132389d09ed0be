#!/usr/bin/env bash
# Create or update .venv with the exact pins of requirements.txt, then fix the ROS wheels' CMake
# files for this interpreter.  Called by `make build` only when requirements.txt (or this script)
# changed since the last successful run, so a second `make build` installs nothing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
venv="$root/.venv"

pick_python() {
  # Python 3.10-3.12: the versions the ROS 2 Jazzy wheels are built for.
  local candidate
  for candidate in "${PYTHON:-}" python3 python3.12 python3.11 python3.10; do
    [ -n "$candidate" ] || continue
    command -v "$candidate" >/dev/null 2>&1 || continue
    if "$candidate" -c 'import sys; sys.exit(0 if (3, 10) <= sys.version_info[:2] <= (3, 12) else 1)'; then
      echo "$candidate"
      return 0
    fi
  done
  echo "setup_venv: need Python 3.10, 3.11 or 3.12 (set PYTHON=/path/to/python3.x)" >&2
  return 1
}

if [ ! -x "$venv/bin/python" ]; then
  python=$(pick_python)
  echo "setup_venv: creating .venv with $($python --version)"
  "$python" -m venv "$venv"
fi
# Exact pins per interpreter: requirements-py3XX.txt where one exists, else requirements.txt (3.11).
version=$("$venv/bin/python" -c 'import sys; print(f"{sys.version_info[0]}{sys.version_info[1]}")')
requirements="$root/requirements-py$version.txt"
[ -f "$requirements" ] || requirements="$root/requirements.txt"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$requirements"
"$venv/bin/python" "$root/tools/fix_ros_wheel_cmake.py" "$venv"
touch "$venv/.wurde-installed"
