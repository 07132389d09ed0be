"""The manual's examples run as written (docs/simulator.md, docs/vision.md): the dummy robot (the
MCP brings the dummies up, tour drives) and the Eye's camera (an ImageSource whose frames the
Eye's page serves)."""

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
from wurde_testing.manual import example, section

ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_readme_dummy_robot_example(ros_domain: int, tmp_path: pathlib.Path) -> None:
    block = example('dummy-robot', 'bash')
    assert block.startswith('source env.sh')
    env = dict(os.environ, WURDE_DATA_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    result = subprocess.run(['bash', '-c', block], env=env, cwd=ROOT, capture_output=True, text=True,
                            timeout=300, check=False)
    assert 'tour: all of 2 waypoints reached' in result.stdout, result.stdout[-3000:] + result.stderr[-3000:]
    assert result.returncode == 0, result.stderr[-3000:]
    assert (tmp_path / 'tour.png').read_bytes()[:4] == b'\x89PNG'
    assert (tmp_path / 'mcp-modules' / 'PlutoLaser.log').read_text().rstrip().endswith('--- exit code 0')


def test_readme_vision_operator_example_runs_as_a_plugin(tmp_path: pathlib.Path) -> None:
    """The "how to write an operator" class, loaded from a <plugin path> file, processes frames."""
    import numpy as np

    from wurde_drivers.vision.camera import Frame
    from wurde_drivers.vision.operator import OperatorContext
    from wurde_drivers.vision.registry import load_plugins, operator_class
    from wurde_drivers.vision.vision_config import load_vision_config

    (tmp_path / 'my_operators.py').write_text(example('vision-operator', 'python'))
    config = tmp_path / 'vision-config.xml'
    config.write_text('<?xml version="1.0"?>\n<vision-config>\n<module name="M"><camera name="c"/>\n'
                      '<operator name="Edges" type="EdgeCounter" camera="c"><option name="every" value="2"/>'
                      '</operator></module>\n<plugin path="my_operators.py"/>\n</vision-config>\n')
    vision = load_vision_config(config)
    spec = vision.module('M').operators[0]
    operator = operator_class(spec, load_plugins(vision.plugins, lambda _: None))(spec)

    class Lines:
        def __init__(self) -> None:
            self.lines: list[str] = []

        def info_msg(self, text: str) -> None:
            self.lines.append(text)

    logger = Lines()
    operator.setup(OperatorContext(None, logger, str(tmp_path)))
    image = np.zeros((40, 40, 3), np.uint8)
    image[10:30, 10:30] = 255                 # a square: edges on its outline
    for index in range(4):
        operator.process({'c': Frame('c', index, 0.0, image)})
    assert len(logger.lines) == 2 and logger.lines[0].startswith('Edges: frame 0: ')
    assert int(logger.lines[0].split()[3]) > 0


def test_readme_vision_sim_example(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The simulated robot's eyes as the manual runs them: frames written that show walls."""
    import cv2
    import numpy as np

    block = example('vision-sim', 'bash')
    assert block.startswith('source env.sh')
    env = dict(os.environ, WURDE_DATA_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path))
    result = subprocess.run(['bash', '-c', block], env=env, cwd=ROOT, capture_output=True, text=True,
                            timeout=120, check=False)
    assert result.returncode == 0, result.stderr[-3000:]
    written = sorted(tmp_path.glob('eyes-*-main-*.ppm'))
    assert written and result.stdout.split()[-1] == str(len(written)), result.stdout + result.stderr[-3000:]
    image = cv2.imread(str(written[-1]))
    assert image.shape == (240, 320, 3)
    from wurde_drivers.sim.render import CEILING, FLOOR
    horizon = image[120]      # every column of the office's start room meets a wall there
    assert not np.any(np.all(horizon == FLOOR, axis=1)) and not np.any(np.all(horizon == CEILING, axis=1))


def test_readme_eye_camera_example(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The manual's ImageSource camera runs as written, and the Eye (no DISPLAY: its page) serves
    its frames exactly: pixel (x, y) of frame k is ((x + 4k) % 256, y, 128)."""
    block = example('eye-camera', 'python')
    camera = tmp_path / 'camera.py'
    camera.write_text(block)
    assert 'eye -i Camera' in section('The Eye (`eye`, WURDE 7.8)')
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


def test_readme_teleop_example(ros_domain: int, tmp_path: pathlib.Path) -> None:
    """The Teleoperation example, on a copy of config/blind-teleop with the joystick FIFO in the
    test's directory (tests run side by side): the stick's input reaches blind_teleop, whose
    status line shows the relative goal it asked for and the robot's odometry going forward, and the
    quit button ends it with status 0."""
    block = example('teleop', 'bash')
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
