"""The README's examples run as written: the dummy robot (the MCP brings the dummies up, tour
drives) and the Eye's camera (an ImageSource whose frames the Eye's page serves)."""

from __future__ import annotations

import os
import pathlib
import re
import subprocess
import urllib.request

import cv2
import numpy as np
from eye_fixture import eye
from wurde_testing import ChildProcess

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


def test_readme_eye_camera_example(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The README's ImageSource camera runs as written, and the Eye (no DISPLAY: its page) serves
    its frames exactly: pixel (x, y) of frame k is ((x + 4k) % 256, y, 128)."""
    text = (ROOT / 'README.md').read_text()
    start = text.index('<!-- example: eye-camera -->')
    block = re.compile(r'```python\n(.*?)```', re.S).search(text, start).group(1)
    camera = tmp_path / 'camera.py'
    camera.write_text(block)
    assert 'eye -i Camera' in text[start:text.index('## Navigation', start)]
    with ChildProcess([str(camera)]) as supplier, \
            eye(['-i', 'Camera', '-p', '0'], display=None) as child:
        url = re.search(r'http://127\.0\.0\.1:\d+/', child.expect('shows Camera on http://', 30))
        assert url, child.stdout
        with urllib.request.urlopen(url.group(0) + 'frame.png?after=0',  # noqa: S310 - loopback
                                    timeout=30) as answer:
            k = int(answer.headers['X-Source-Frame'])
            png = np.frombuffer(answer.read(), np.uint8)
    shown = cv2.cvtColor(cv2.imdecode(png, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
    x, y = np.meshgrid(np.arange(320), np.arange(240))
    expected = np.dstack(((x + 4 * k) % 256, y, np.full_like(x, 128)))
    assert k >= 1 and (shown == expected).all()
    assert supplier.process.returncode == 0, supplier.stderr[-3000:]
    assert child.process.returncode == 0, child.stderr[-3000:]
