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


def test_readme_teleop_example(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The Teleoperation example, on a copy of config/blind-teleop with the joystick FIFO in the
    test's directory (tests run side by side): the stick's input reaches blind_teleop, whose
    status line shows the relative goal it asked for and the robot's odometry going forward, and the
    quit button ends it with status 0."""
    text = (ROOT / 'README.md').read_text()
    start = text.index('<!-- example: teleop -->')
    block = re.compile(r'```bash\n(.*?)```', re.S).search(text, start).group(1)
    assert block.startswith('source env.sh')
    config, fifo = tmp_path / 'config', str(tmp_path / 'js0')
    config.mkdir()
    for source in (ROOT / 'config' / 'blind-teleop').glob('*.xml'):
        (config / source.name).write_text(source.read_text().replace('/tmp/wurde-joystick', fifo)
                                          .replace('../maps/', f'{ROOT}/config/maps/'))
    assert block.count('config/blind-teleop') == 1 and block.count('/tmp/wurde-joystick') == 1
    block = block.replace('config/blind-teleop', str(config)).replace('/tmp/wurde-joystick', fifo)
    env = dict(os.environ, WURDE_LOG_DIRECTORY=str(tmp_path))
    result = subprocess.run(['bash', '-c', block], env=env, cwd=ROOT, capture_output=True, text=True,
                            timeout=300, check=False)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert 'reader 1 opened the joystick' in result.stdout, result.stdout[-3000:]
    log = (tmp_path / 'mcp-modules' / 'BlindTeleop.log').read_text().rsplit(' start: ', 1)[-1]
    assert 'Relative Goal: (0.976592,0.000000)' in log, log[-3000:]   # -16000: 16000/32767*2 m
    assert 'quit button' in log and log.rstrip().endswith('--- exit code 0'), log[-3000:]
    x = float(re.findall(r'Location: \(([-0-9.]+),', log)[-1])
    assert x > 0.3, f'the robot drove {x} m'     # started at 0 in its odometry frame
