"""Reader of ``laser-config.xml``, the SICKServer's device file (WURDE guide 7.5).

The root ``<laser-config>`` holds one or more ``<device>`` elements.  Required attributes (7.5):
``port`` (the serial port), ``name`` (unique; the module picks its device by its ``-n`` name),
``type`` (``PLS`` or ``LMS``).  Optional (7.5): ``invert`` (mounted upside down) and ``log``
(readings to ``LaserLog.txt``), both ``true``/``false``, default false.

Optional attributes of ours, with their defaults (Pluto 8.1's: cm, 361 values, 38400 baud):

- ``baud``: 9600, 19200, 38400 or 500000 (default 38400; 500000 needs RS-422);
- ``resolution``: degrees between beams over 180°, ``1.0`` (181 values) or ``0.5`` (361, default);
- ``units``: ``cm`` (81.91 m max, default) or ``mm`` (8.191 m max).  A PLS runs at 0.5° in cm only.

Example::

    <laser-config>
      <device port="/dev/ttyS0" name="laser" type="LMS" invert="false" log="false"/>
    </laser-config>
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree

from .xml_config import Attributes, device_named, read_devices

__all__ = ['LaserDevice', 'device_named', 'load_laser_config']

_BAUDS = ('9600', '19200', '38400', '500000')
_RESOLUTIONS = {'1.0': 1.0, '1': 1.0, '0.5': 0.5}


@dataclasses.dataclass(frozen=True)
class LaserDevice:
    """One ``<device>`` of a laser-config file, with where it was read (``path``, ``line``)."""

    port: str
    name: str
    type: str
    invert: bool = False
    log: bool = False
    baud: int = 38400
    resolution: float = 0.5
    units: str = 'cm'
    path: str = ''
    line: int | None = None

    @property
    def values(self) -> int:
        """Values per scan: 181 at 1°, 361 at 0.5°."""
        return 181 if self.resolution == 1.0 else 361


def _device(path: str, node: etree._Element) -> LaserDevice:
    attributes = Attributes(path, node, required=('port', 'name', 'type'),
                            optional=('invert', 'log', 'baud', 'resolution', 'units'))
    kind = attributes.choice('type', ('PLS', 'LMS'))
    resolution_text = attributes.text('resolution', '0.5')
    if resolution_text not in _RESOLUTIONS:
        raise attributes.error(f'attribute resolution="{resolution_text}" of <device> must be '
                               f'1.0 or 0.5')
    device = LaserDevice(
        port=attributes.text('port'), name=attributes.text('name'), type=kind,
        invert=attributes.boolean('invert', False), log=attributes.boolean('log', False),
        baud=int(attributes.choice('baud', _BAUDS, '38400')),
        resolution=_RESOLUTIONS[resolution_text],
        units=attributes.choice('units', ('cm', 'mm'), 'cm'),
        path=path, line=node.sourceline)
    if kind == 'PLS' and (device.resolution != 0.5 or device.units != 'cm'):
        raise attributes.error('a PLS runs at resolution 0.5 in cm only')
    return device


def load_laser_config(path: str | os.PathLike[str]) -> list[LaserDevice]:
    """Every device of the file, in order.

    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element or
        attribute, a missing required attribute, a bad value, a duplicate name, no device at all.
    """
    return read_devices(path, 'laser-config', _device)
