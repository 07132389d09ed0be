"""Reader of ``wrist-config.xml``, the wrist module's device file (Pluto Software Documentation 8.3).

Pluto's wristModule had no documented configuration file; the format follows WURDE's device files
(``laser-config``, guide 7.5)::

    <wrist-config>
      <device name="PlutoWrist" interface="socketcan" channel="can0" pan-id="1" tilt-id="2"/>
    </wrist-config>

- ``name`` (unique; the module picks its device by its ``-n`` name), ``interface`` (a python-can
  interface name: ``socketcan`` on the robot, ``virtual`` for trying it) and ``channel`` (the
  interface's channel: ``can0``, or any name on the virtual bus) are required;
- ``pan-id``, ``tilt-id``: the CAN module addresses of the two axes, 1..31, different (default
  1 and 2, see :mod:`wurde_drivers.wrist.codec`);
- ``emulate`` (true/false, default false): the module hosts the wrist emulator itself on the same
  channel -- the no-hardware mode. python-can's virtual bus connects buses inside one process
  only (docs/protocols.md 5), so the emulator must live in the module's process; hence ``emulate``
  is refused unless ``interface="virtual"``;
- ``mount-x``, ``mount-y``, ``mount-z``, ``mount-yaw``: where the wrist's base sits on the robot
  (:mod:`wurde_drivers.mounting`, default 0).

``udp_multicast`` is refused: it would carry the bus out over the network (docs/protocols.md 5).
"""

from __future__ import annotations

import dataclasses
import os

from can.interfaces import VALID_INTERFACES
from lxml import etree

from ..mounting import MOUNT_ATTRIBUTES, Mounting, read_mounting
from ..xml_config import Attributes, device_named, read_devices

__all__ = ['WristDevice', 'device_named', 'load_wrist_config']

ROOT_TAG = 'wrist-config'
_REFUSED = {'udp_multicast': 'it sends the bus out over the network'}


@dataclasses.dataclass(frozen=True)
class WristDevice:
    """One ``<device>`` of a wrist-config file, with where it was read (``path``, ``line``)."""

    name: str
    interface: str
    channel: str
    pan_id: int = 1
    tilt_id: int = 2
    emulate: bool = False
    path: str = ''
    line: int | None = None
    mount: Mounting = Mounting()  # where it sits on the robot (mounting)


def _device(path: str, node: etree._Element) -> WristDevice:
    attrs = Attributes(path, node, required=('name', 'interface', 'channel'),
                       optional=('pan-id', 'tilt-id', 'emulate', *MOUNT_ATTRIBUTES))
    interface = attrs.text('interface')
    if interface in _REFUSED:
        raise attrs.error(f'interface="{interface}" is refused: {_REFUSED[interface]}')
    if interface not in VALID_INTERFACES:
        raise attrs.error(f'interface="{interface}" of <device> is not a python-can interface '
                          f'(one of {", ".join(sorted(set(VALID_INTERFACES) - set(_REFUSED)))})')
    pan_id = attrs.number('pan-id', 1, minimum=1, maximum=31, integer=True)
    tilt_id = attrs.number('tilt-id', 2, minimum=1, maximum=31, integer=True)
    if pan_id == tilt_id:
        raise attrs.error(f'pan-id and tilt-id are both {pan_id}; the axes need their own ids')
    emulate = attrs.boolean('emulate', False)
    if emulate and interface != 'virtual':
        raise attrs.error(f'emulate="true" needs interface="virtual" (got "{interface}"): the '
                          'emulated wrist lives on python-can\'s virtual bus in the module\'s '
                          'own process')
    return WristDevice(name=attrs.text('name'), interface=interface,
                       channel=attrs.text('channel'), pan_id=pan_id, tilt_id=tilt_id,
                       emulate=emulate, mount=read_mounting(attrs), path=path, line=attrs.line)


def load_wrist_config(path: str | os.PathLike[str]) -> list[WristDevice]:
    """Every device of the file, in order.

    :param path: the wrist-config.xml to read.
    :raises ConfigError: naming the file and line: malformed XML, wrong root, unknown element or
        attribute, a missing required attribute, a bad value, a duplicate name, no device at all.
    """
    return read_devices(path, ROOT_TAG, _device)
