"""The README's dummy-robot example runs as written: the MCP brings the dummies up, tour drives."""

from __future__ import annotations

import os
import pathlib
import re
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_readme_dummy_robot_example(ros_domain: int, tmp_path: pathlib.Path) -> None:
    text = (ROOT / 'README.md').read_text()
    start = text.index('<!-- example: dummy-robot -->')
    block = re.compile(r'```bash\n(.*?)```', re.S).search(text, start).group(1)
    assert block.startswith('source env.sh')
    env = dict(os.environ, WURDE_DATA_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    result = subprocess.run(['bash', '-c', block], env=env, cwd=ROOT, capture_output=True, text=True,
                            timeout=300, check=False)
    assert 'tour: all of 2 waypoints reached' in result.stdout, result.stdout[-3000:] + result.stderr[-3000:]
    assert result.returncode == 0, result.stderr[-3000:]
    assert (tmp_path / 'tour.png').read_bytes()[:4] == b'\x89PNG'
    assert (tmp_path / 'mcp-modules' / 'PlutoLaser.log').read_text().rstrip().endswith('--- exit code 0')
