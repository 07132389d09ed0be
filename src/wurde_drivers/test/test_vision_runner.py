"""The VisionModule's turn without ROS: frames go to the operators of their camera, an operator
that raises is stopped and reported while the others go on, and options change at run time as
VisionControl's set option does (checked as the config's are)."""

from __future__ import annotations

import pathlib
import time
from collections.abc import Mapping

import cv2
import numpy as np
import pytest
from wurde_idl.errors import ConfigError

from wurde_drivers.vision import Frame, Operator, OperatorContext, OperatorSpec
from wurde_drivers.vision.camera_config import CameraSpec
from wurde_drivers.vision.operators.image_writer import ImageWriter
from wurde_drivers.vision.playback import PlaybackCamera, image_name
from wurde_drivers.vision.runner import VisionRunner
from wurde_drivers.vision.vision_config import ModuleLayout


class Log:
    def __init__(self) -> None:
        self.lines: list[str] = []

    def error(self, text: str) -> None:
        self.lines.append(text)

    warn = error


class Broken(Operator):
    def process(self, frames: Mapping[str, Frame]) -> None:
        raise RuntimeError('a bug in an operator')


def test_a_failing_operator_stops_alone(tmp_path: pathlib.Path) -> None:
    (tmp_path / 'in').mkdir()
    for i in range(5):
        cv2.imwrite(str(tmp_path / 'in' / image_name('', i, 'main', 10.0 + i, '.ppm')),
                    np.full((24, 32, 3), 40 * i, np.uint8))
    camera = PlaybackCamera(CameraSpec('Cam', 'playback', {
        'imageDirectory': str(tmp_path / 'in'), 'imagePrefix': '', 'imageDevice': 'main',
        'imageSuffix': '.ppm', 'frameRate': '0', 'loop': 'false'}), lambda _: None)
    writer = ImageWriter(OperatorSpec('W', 'ImageWriter', ('Cam',), {'imageDir': str(tmp_path / 'out')}))
    broken = Broken(OperatorSpec('B', 'Broken', ('Cam',), {}))
    log = Log()
    runner = VisionRunner(ModuleLayout('L', ('Cam',), ()), [camera], [broken, writer], log)
    context = OperatorContext(None, log, str(tmp_path))
    for operator in (broken, writer):
        operator.setup(context)
    deadline = time.monotonic() + 10
    while not camera.finished:
        assert time.monotonic() < deadline
        runner.step()
    assert not broken.running and writer.running and writer.written == 5 and runner.frame_count == 5
    assert log.lines == ["operator B stopped: RuntimeError('a bug in an operator')"]
    assert sorted(p.name for p in (tmp_path / 'out').iterdir())[0] == 'W-0-main-10.000000.ppm'
    # Set option at run time: a new directory is used; an unknown option or bad value refused.
    writer.set_option('imageDir', str(tmp_path / 'elsewhere'))
    assert writer.directory == str(tmp_path / 'elsewhere') and (tmp_path / 'elsewhere').is_dir()
    with pytest.raises(ConfigError, match='ImageWriter has no option size'):
        writer.set_option('size', '2')
    runner.close()
    runner.close()
