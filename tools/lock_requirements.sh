#!/usr/bin/env bash
# Re-pin requirements.txt from requirements.in: install into a scratch venv, then write every
# distribution pip installed (dist-info with an INSTALLER file) as name==version.
# The ROS wheels also carry egg-info records of their colcon builds (rclpy, std_msgs, ...):
# those are not PyPI names and must not be pinned, which is why this is not `pip freeze`.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
python=${PYTHON:-python3}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$python" -m venv "$scratch/venv"
"$scratch/venv/bin/pip" install -q -r "$here/requirements.in"
{
  sed -n '1,/^$/p' "$here/requirements.txt" | grep '^#'
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
} > "$here/requirements.txt.new"
mv "$here/requirements.txt.new" "$here/requirements.txt"
echo "requirements.txt: $(grep -c '==' "$here/requirements.txt") pins"
