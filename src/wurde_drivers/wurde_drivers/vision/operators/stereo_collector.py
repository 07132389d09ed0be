"""StereoDataCollector: one or two cameras, a RangeFinder and an Egomotion logged together
(WURDE guide 7.2.3).

At every frame of its first camera the collector takes the newest data of each source and saves
the set under one more frame index of its own (counted from 0), each file keeping its source's
own timestamp, as the guide names them:

``imagePrefix-[frame index]-device-[timestamp in seconds].suffix``, device one of

- ``main`` (the first camera) and ``stereo`` (the second, if any): ``.ppm`` images;
- ``laser``: ``.txt``, the RangeFinder's readings as plain numbers separated by spaces
  (no header, just data);
- ``odometry``: ``.txt``, ``x y theta tv rv`` (m, rad, m/s, rad/s; no commas).

A source that has sent nothing yet is left out of the set; each file appears whole (written
under a hidden name, then renamed), the odometry last. Options: ``imageDir`` (default the
WURDE data directory), ``imagePrefix`` (default the operator's name), and ours: ``laser`` and
``odometry``, the stream names of the sources (empty: asked of the MCP, ``ConnectionStrategy.AUTO``).
The set can be played back by ``playback`` cameras with ``imageDevice`` main and stereo.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

from wurde_core import ConnectionStrategy
from wurde_core.interfaces import Egomotion, RangeFinder

from ..camera import Frame
from ..operator import Operator, OperatorContext
from ..vision_config import OperatorSpec
from ..playback import image_name
from .files import output_place, write_image, write_text

__all__ = ['StereoDataCollector', 'laser_text', 'odometry_text']


def laser_text(ranges: Sequence[float]) -> str:
    """One reading as the guide's laser file holds it: numbers only."""
    return ' '.join(repr(float(value)) for value in ranges) + '\n'


def odometry_text(x: float, y: float, theta: float, tv: float, rv: float) -> str:
    """One odometry line: ``x y theta tv rv``."""
    return ' '.join(repr(float(value)) for value in (x, y, theta, tv, rv)) + '\n'


class StereoDataCollector(Operator):
    OPTIONS = {'imageDir': '', 'imagePrefix': '', 'laser': '', 'odometry': ''}
    CAMERAS = (1, 2)

    def __init__(self, spec: OperatorSpec) -> None:
        super().__init__(spec)
        self.directory = ''
        self.prefix = ''
        self.sets = 0
        self.failed = 0      # files that could not be written
        self.laser: RangeFinder | None = None
        self.odometry: Egomotion | None = None
        self._laser: tuple[float, list[float]] | None = None
        self._odometry: tuple[float, str] | None = None

    def setup(self, context: OperatorContext) -> None:
        super().setup(context)
        self.configure()
        laser, odometry = self.options['laser'], self.options['odometry']
        self.laser = RangeFinder(laser) if laser else RangeFinder(ConnectionStrategy.AUTO, f'{self.name}Laser')
        self.odometry = (Egomotion(odometry) if odometry
                         else Egomotion(ConnectionStrategy.AUTO, f'{self.name}Odometry'))
        context.manager.register_consumer(self.laser)
        context.manager.register_consumer(self.odometry)

    def configure(self) -> None:
        self.directory, self.prefix = output_place(self)

    def _take(self) -> None:
        assert self.laser is not None and self.odometry is not None
        while self.laser.get_next_data():
            data = self.laser.data
            self._laser = (data.timestamp.get_seconds(), list(data.ranges))
        while self.odometry.get_next_data():
            data = self.odometry.data
            loc = data.location
            self._odometry = (data.timestamp.get_seconds(),
                              odometry_text(loc.x(), loc.y(), loc.theta(), data.tv, data.rv))

    def _path(self, device: str, stamp: float, suffix: str) -> str:
        return os.path.join(self.directory, image_name(self.prefix, self.sets, device, stamp, suffix))

    def process(self, frames: Mapping[str, Frame]) -> None:
        self._take()
        for device, camera in zip(('main', 'stereo'), self.cameras):
            frame = frames.get(camera)
            if frame is not None:
                ok = write_image(self._path(device, frame.stamp, '.ppm'), frame.image)
                self._count(ok)
        if self._laser is not None:
            self._count(write_text(self._path('laser', self._laser[0], '.txt'), laser_text(self._laser[1])))
        if self._odometry is not None:
            self._count(write_text(self._path('odometry', self._odometry[0], '.txt'), self._odometry[1]))
        self.sets += 1

    def _count(self, ok: bool) -> None:
        if not ok:
            self.failed += 1
            if self.failed == 1:
                self.context.logger.warn(f'{self.name}: cannot write to {self.directory}; '
                                         'sets are incomplete until it can')
