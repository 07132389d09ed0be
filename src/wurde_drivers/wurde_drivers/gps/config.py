"""Reader of ``gps-config.xml``, the GPS module's device file (Pluto Software Documentation 8.4).

Pluto's gpsModule had no documented configuration file; the format follows WURDE's device files
(``laser-config``, guide 7.5)::

    <gps-config>
      <device port="/dev/ttyS3" name="PlutoGPS" baud="4800"
              origin-latitude="59.3498" origin-longitude="18.0707"
              min-satellites="6" min-quality="2"/>
    </gps-config>

- ``port`` (a serial port or pyserial URL) and ``name`` (unique; the module picks its device by
  its ``-n`` name) are required;
- ``baud``: 4800 (NMEA 0183, the default), 9600 or 38400;
- ``origin-latitude`` and ``origin-longitude`` (degrees, both or neither): the origin of the
  local x (east), y (north) grid in metres; without them the first good fix is the origin;
- ``min-satellites`` (default 6) and ``min-quality`` (default 2): what a good fix needs (Pluto
  8.4: "> 5 satellites and quality 2 for sub-meter accuracy"); the quality is a GGA code ranked
  by accuracy (:mod:`~wurde_drivers.gps.quality`): 0 (any measured fix), 1, 3, 2, 5 or 4 — never
  6 to 9, which measure nothing;
- ``timeout``: seconds without a sentence before the receiver counts as silent (default 3);
- ``mount-x``, ``mount-y``, ``mount-z``: where the antenna sits on the robot
  (:mod:`wurde_drivers.mounting`, default 0).
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree

from ..mounting import MOUNT_XYZ, Mounting, read_mounting
from ..xml_config import Attributes, device_named, read_devices
from .quality import MINIMUMS

__all__ = ['GpsDevice', 'device_named', 'load_gps_config']

ROOT_TAG = 'gps-config'
_BAUDS = ('4800', '9600', '38400')


@dataclasses.dataclass(frozen=True)
class GpsDevice:
    """One ``<device>`` of a gps-config file, with where it was read (``path``, ``line``).

    ``origin`` is (latitude, longitude) in degrees, or None: the first good fix.
    """

    port: str
    name: str
    baud: int = 4800
    origin: tuple[float, float] | None = None
    min_satellites: int = 6
    min_quality: int = 2
    timeout: float = 3.0
    path: str = ''
    line: int | None = None
    mount: Mounting = Mounting()  # where it sits on the robot (mounting)


def _min_quality(attrs: Attributes) -> int:
    """``min-quality``: a GGA quality a fix can be required to have (not 6 dead reckoning, ...)."""
    value = int(attrs.number('min-quality', 2, minimum=0, maximum=9, integer=True))
    if value not in MINIMUMS:
        raise attrs.error(f'attribute min-quality={value} of <device> is no measured fix quality: '
                          f'use one of {", ".join(map(str, MINIMUMS))} (0 any, 2 DGPS, 4/5 RTK)')
    return value


def _device(path: str, node: etree._Element) -> GpsDevice:
    attrs = Attributes(path, node, required=('port', 'name'),
                       optional=('baud', 'origin-latitude', 'origin-longitude', 'min-satellites',
                                 'min-quality', 'timeout', *MOUNT_XYZ))
    origin = None
    given = [attrs.has('origin-latitude'), attrs.has('origin-longitude')]
    if any(given):
        if not all(given):
            raise attrs.error('<device> needs both origin-latitude and origin-longitude, or '
                              'neither (then the first good fix is the origin)')
        origin = (float(attrs.number('origin-latitude', minimum=-90.0, maximum=90.0)),
                  float(attrs.number('origin-longitude', minimum=-180.0, maximum=180.0)))
    timeout = float(attrs.number('timeout', 3.0))
    if not timeout > 0:
        raise attrs.error(f'attribute timeout={timeout} of <device> must be above 0 s')
    return GpsDevice(
        port=attrs.text('port'), name=attrs.text('name'),
        baud=int(attrs.choice('baud', _BAUDS, '4800')), origin=origin,
        min_satellites=attrs.number('min-satellites', 6, minimum=0, maximum=64, integer=True),
        min_quality=_min_quality(attrs),
        timeout=timeout, mount=read_mounting(attrs), path=path, line=attrs.line)


def load_gps_config(path: str | os.PathLike[str]) -> list[GpsDevice]:
    """Every device of the file, in order.

    :param path: the gps-config.xml to read.
    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element or
        attribute, a missing required attribute, a bad value, a duplicate name, no device at all.
    """
    return read_devices(path, ROOT_TAG, _device)
