"""Reader of ``laser-config.xml``, the SICKServer's device file (WURDE guide 7.5).

The root ``<laser-config>`` holds one or more ``<device>`` elements.  Required attributes (7.5):
``port`` (the serial port), ``name`` (unique; the module picks its device by its ``-n`` name),
``type`` (``PLS`` or ``LMS``).  Optional (7.5): ``invert`` (mounted upside down) and ``log``
(readings to ``LaserLog.txt``), both ``true``/``false``, default false.

Optional attributes of ours, with their defaults (Pluto 8.1's: cm, 361 values, 38400 baud):

- ``baud``: 9600, 19200, 38400 or 500000 (default 38400; 500000 needs RS-422);
- ``resolution``: degrees between beams over 180°, ``1.0`` (181 values) or ``0.5`` (361, default);
- ``units``: ``cm`` (81.82 m max, default) or ``mm`` (8.182 m max).  A PLS runs at 0.5° in cm only;
- ``parity``: ``none`` or ``even``, default the device's own: ``even`` for a PLS (8E1), ``none``
  for an LMS (8N1).  Say ``none`` for a PLS on a pseudo-terminal, e.g. ``sick_emulator``'s link:
  a pty cannot carry parity (docs/protocols.md 6: reconfiguring it with PARENB fails with EINVAL);
- ``mount-x``, ``mount-y``, ``mount-z``: where the laser sits on the robot, m
  (:mod:`wurde_drivers.mounting`; default 0, 0, 0.4).

Example::

    <laser-config>
      <device port="/dev/ttyS0" name="laser" type="LMS" invert="false" log="false"/>
      <device port="/tmp/wurde-sick-rear" name="rear" type="PLS" parity="none"/>
    </laser-config>
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree

from ..mounting import MOUNT_XYZ, Mounting, read_mounting
from ..xml_config import Attributes, device_named, read_devices
from . import facts

__all__ = ['DEFAULT_PARITY', 'LaserDevice', 'SickDevice', 'device_named', 'load_laser_config']

_BAUDS = ('9600', '19200', '38400', '500000')
_RESOLUTIONS = {'1.0': 1.0, '1': 1.0, '0.5': 0.5}
#: The line parity each type speaks (docs/protocols.md 1.1: a PLS is 8E1, an LMS 8N1).
DEFAULT_PARITY = {'PLS': 'even', 'LMS': 'none'}


@dataclasses.dataclass(frozen=True)
class SickDevice:
    """One ``<device>`` of a laser-config file, with where it was read (``path``, ``line``).

    ``parity`` is ``'none'`` or ``'even'``; left empty it becomes the type's :data:`DEFAULT_PARITY`.
    """

    port: str
    name: str
    type: str
    invert: bool = False
    log: bool = False
    baud: int = 38400
    resolution: float = 0.5
    units: str = 'cm'
    parity: str = ''
    path: str = ''
    line: int | None = None
    mount: Mounting = Mounting(z=0.4)  # where it sits on the robot (mounting)

    def __post_init__(self) -> None:
        if not self.parity:
            object.__setattr__(self, 'parity', DEFAULT_PARITY.get(self.type, 'none'))

    @property
    def values(self) -> int:
        """Values per scan: 181 at 1°, 361 at 0.5°."""
        return facts.VALUES_AT[self.resolution]


def _device(path: str, node: etree._Element) -> SickDevice:
    attributes = Attributes(path, node, required=('port', 'name', 'type'),
                            optional=('invert', 'log', 'baud', 'resolution', 'units', 'parity',
                                      *MOUNT_XYZ))
    kind = attributes.choice('type', ('PLS', 'LMS'))
    resolution_text = attributes.text('resolution', '0.5')
    if resolution_text not in _RESOLUTIONS:
        raise attributes.error(f'attribute resolution="{resolution_text}" of <device> must be '
                               f'1.0 or 0.5')
    device = SickDevice(
        port=attributes.text('port'), name=attributes.text('name'), type=kind,
        invert=attributes.boolean('invert', False), log=attributes.boolean('log', False),
        baud=int(attributes.choice('baud', _BAUDS, '38400')),
        resolution=_RESOLUTIONS[resolution_text],
        units=attributes.choice('units', ('cm', 'mm'), 'cm'),
        parity=attributes.choice('parity', ('none', 'even'), DEFAULT_PARITY[kind]),
        mount=read_mounting(attributes, z=0.4), path=path, line=node.sourceline)
    if kind == 'PLS' and facts.variant_error(kind, device.values, device.units) is not None:
        raise attributes.error('a PLS runs at resolution 0.5 in cm only')
    return device


def load_laser_config(path: str | os.PathLike[str]) -> list[SickDevice]:
    """Every device of the file, in order.

    :param path: the laser-config.xml to read.
    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element or
        attribute, a missing required attribute, a bad value, a duplicate name, no device at all.
    """
    return read_devices(path, 'laser-config', _device)


LaserDevice = SickDevice  # old name (docs/naming.md)
