"""Reader of ``ptu-config.xml``, the PTU Server's device file (WURDE guide 7.4).

The guide gives the PTU Server no documented configuration; the format follows WURDE's device
files (``laser-config``, guide 7.5)::

    <ptu-config>
      <device port="/dev/ttyS1" name="PTU" baud="9600" rate="10"/>
    </ptu-config>

- ``port`` (a serial port or pyserial URL) and ``name`` (unique; the module picks its device by
  its ``-n`` name) are required;
- ``baud``: the unit's line speed, 600 to 38400 (default 9600, the PTU-46's factory setting,
  docs/protocols.md 2);
- ``rate``: how often the measured pan and tilt are read and published, in Hz (1 to 30, default
  10; each reading is four round trips on the line);
- ``mount-x``, ``mount-y``, ``mount-z``, ``mount-yaw``: where the unit's base sits on the robot
  (:mod:`wurde_drivers.mounting`, default 0).
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree

from ..mounting import MOUNT_ATTRIBUTES, Mounting, read_mounting
from ..xml_config import Attributes, device_named, read_devices

__all__ = ['PtuDevice', 'device_named', 'load_ptu_config']

ROOT_TAG = 'ptu-config'
_BAUDS = ('600', '1200', '2400', '4800', '9600', '19200', '38400')


@dataclasses.dataclass(frozen=True)
class PtuDevice:
    """One ``<device>`` of a ptu-config file, with where it was read (``path``, ``line``)."""

    port: str
    name: str
    baud: int = 9600
    rate: float = 10.0
    path: str = ''
    line: int | None = None
    mount: Mounting = Mounting()  # where it sits on the robot (mounting)


def _device(path: str, node: etree._Element) -> PtuDevice:
    attrs = Attributes(path, node, required=('port', 'name'), optional=('baud', 'rate', *MOUNT_ATTRIBUTES))
    return PtuDevice(port=attrs.text('port'), name=attrs.text('name'),
                     baud=int(attrs.choice('baud', _BAUDS, '9600')),
                     rate=float(attrs.number('rate', 10.0, minimum=1.0, maximum=30.0)),
                     mount=read_mounting(attrs), path=path, line=attrs.line)


def load_ptu_config(path: str | os.PathLike[str]) -> list[PtuDevice]:
    """Every device of the file, in order.

    :param path: the ptu-config.xml to read.
    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element or
        attribute, a missing required attribute, a bad value, a duplicate name, no device at all.
    """
    return read_devices(path, ROOT_TAG, _device)
