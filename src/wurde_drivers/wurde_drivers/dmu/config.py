"""Reader of ``dmu-config.xml``, the DMU module's device file (Pluto Software Documentation 8.2).

Pluto's dmuModule had no documented configuration file; the format follows WURDE's device files
(``laser-config``, guide 7.5)::

    <dmu-config>
      <device port="/dev/ttyS2" name="PlutoDMU" baud="38400" mode="angle" cutoff="5"/>
    </dmu-config>

- ``port`` (a serial port or pyserial URL) and ``name`` (unique; the module picks its device by
  its ``-n`` name) are required;
- ``baud``: 9600, 19200, 38400, 57600 or 115200 (default 38400, the Crossbow default,
  docs/protocols.md 7);
- ``mode``: ``angle`` (roll and pitch from the sensor's own filter, default) or ``scaled``
  (rates and accelerations only; pitch and roll are then published as 0);
- ``cutoff``: the low-pass cut-off of the filtered DMUstate in Hz (> 0, default 5);
- ``mount-x``, ``mount-y``, ``mount-z``: where the unit sits on the robot
  (:mod:`wurde_drivers.mounting`, default 0; its axes are the robot's).
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree

from ..mounting import MOUNT_XYZ, Mounting, read_mounting
from ..xml_config import Attributes, device_named, read_devices
from .codec import DEFAULT_BAUDRATE, DmuMode

__all__ = ['DmuDevice', 'device_named', 'load_dmu_config']

ROOT_TAG = 'dmu-config'
_BAUDS = ('9600', '19200', '38400', '57600', '115200')
_MODES = {'angle': DmuMode.ANGLE, 'scaled': DmuMode.SCALED}


@dataclasses.dataclass(frozen=True)
class DmuDevice:
    """One ``<device>`` of a dmu-config file, with where it was read (``path``, ``line``)."""

    port: str
    name: str
    baud: int = DEFAULT_BAUDRATE
    mode: DmuMode = DmuMode.ANGLE
    cutoff: float = 5.0
    path: str = ''
    line: int | None = None
    mount: Mounting = Mounting()  # where it sits on the robot (mounting)


def _device(path: str, node: etree._Element) -> DmuDevice:
    attrs = Attributes(path, node, required=('port', 'name'),
                       optional=('baud', 'mode', 'cutoff', *MOUNT_XYZ))
    cutoff = attrs.number('cutoff', 5.0)
    if not cutoff > 0:
        raise attrs.error(f'attribute cutoff={cutoff} of <device> must be above 0 Hz')
    return DmuDevice(
        port=attrs.text('port'), name=attrs.text('name'),
        baud=int(attrs.choice('baud', _BAUDS, str(DEFAULT_BAUDRATE))),
        mode=_MODES[attrs.choice('mode', tuple(_MODES), 'angle')],
        cutoff=float(cutoff), mount=read_mounting(attrs), path=path, line=attrs.line)


def load_dmu_config(path: str | os.PathLike[str]) -> list[DmuDevice]:
    """Every device of the file, in order.

    :param path: the dmu-config.xml to read.
    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element or
        attribute, a missing required attribute, a bad value, a duplicate name, no device at all.
    """
    return read_devices(path, ROOT_TAG, _device)
