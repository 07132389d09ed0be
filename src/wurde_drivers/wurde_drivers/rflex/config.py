"""Reader of ``rflex-config.xml``, the RFlexServer's configuration (WURDE guide 7.6).

WURDE 7.6: the file "specifies the RFlex serial device, the type of robot being controlled, and
whether the module should be allowed to reset the brake". The guide leaves the example out
("Insert Example Here"), so the format follows its sibling ``laser-config`` (7.5)::

    <rflex-config>
      <device port="/dev/ttyS0" name="base" type="B21r" brake-reset="true"
              command-timeout="1.0"/>
    </rflex-config>

- ``port``, ``name``, ``type`` (``B21r``, ``ATRVJr``, the appendix's ``B21ir`` (10.1.5: a B21r) or
  Pluto's ``ATRV2``; :data:`wurde_drivers.rflex.robots.ROBOTS`) are required;
- ``brake-reset`` (true/false, default false): may the module release the brake;
- ``command-timeout`` (seconds > 0, default 1.0): the base is stopped when no velocity command
  came for that long.

Names are unique; the module picks its device by its own name (``-n``), as the SICK server does.
"""

from __future__ import annotations

import dataclasses
import os

from lxml import etree

from ..xml_config import Attributes, device_named, read_devices
from .robots import ROBOTS, RobotParams

__all__ = ['RFlexDevice', 'device_named', 'load_rflex_config']

ROOT_TAG = 'rflex-config'


@dataclasses.dataclass(frozen=True)
class RFlexDevice:
    """One ``<device>`` of rflex-config.xml."""

    port: str
    name: str
    type: str
    brake_reset: bool = False
    command_timeout: float = 1.0
    path: str = ''
    line: int | None = None

    @property
    def robot(self) -> RobotParams:
        """The robot parameters of :attr:`type`."""
        return ROBOTS[self.type]


def _device(path: str, node: etree._Element) -> RFlexDevice:
    attrs = Attributes(path, node, required=('port', 'name', 'type'),
                       optional=('brake-reset', 'command-timeout'))
    return RFlexDevice(
        port=attrs.text('port'), name=attrs.text('name'),
        type=attrs.choice('type', tuple(ROBOTS)),
        brake_reset=attrs.boolean('brake-reset', False),
        command_timeout=attrs.number('command-timeout', 1.0, minimum=0.001),
        path=path, line=node.sourceline)


def load_rflex_config(path: str | os.PathLike[str]) -> list[RFlexDevice]:
    """The devices of ``path``.

    :param path: the rflex-config.xml to read.
    :raises ConfigError: with file and line for a malformed file, an unknown element or attribute,
        a missing or bad attribute, no device at all, or a name used twice.
    """
    return read_devices(path, ROOT_TAG, _device)
