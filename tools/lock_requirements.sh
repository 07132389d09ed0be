#!/usr/bin/env bash
# Re-pin from requirements.in for one Python: install into a scratch venv, then write every
# distribution pip installed (dist-info with an INSTALLER file) as name==version.
# Usage: tools/lock_requirements.sh            -> requirements.txt        (python3, 3.11)
#        PYTHON=python3.10 tools/lock_requirements.sh requirements-py310.txt
# tools/setup_venv.sh installs requirements-py3XX.txt when it exists for the interpreter, else
# requirements.txt.  A package pip installs with the legacy setup.py route (empy on Python 3.10)
# leaves no dist-info and is missed: add it by hand (requirements-py310.txt has empy so).
# The ROS wheels also carry egg-info records of their colcon builds (rclpy, std_msgs, ...):
# those are not PyPI names and must not be pinned, which is why this is not `pip freeze`.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-python3}
output="$here/${1:-requirements.txt}"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$python" -m venv "$scratch/venv"
"$scratch/venv/bin/pip" install -q -r "$here/requirements.in"
{
  sed -n '1,/^$/p' "$here/requirements.txt" | grep '^#' | grep -v '^# Interpreter:'
  echo "# Interpreter: $("$python" --version)"
  echo
  "$scratch/venv/bin/python" - <<'PY'
import importlib.metadata as md
import pathlib
pins = set()
for dist in md.distributions():
    path = pathlib.Path(str(dist._path))  # noqa: SLF001 - only way to tell dist-info from egg-info
    if path.suffix == '.dist-info' and (path / 'INSTALLER').exists():
        name = dist.metadata['Name']
        if name.lower() not in ('pip', 'setuptools'):
            pins.add(f'{name}=={dist.version}')
print('\n'.join(sorted(pins, key=str.lower)))
PY
} > "$output.new"
mv "$output.new" "$output"
echo "$(basename "$output"): $(grep -c '==' "$output") pins"
