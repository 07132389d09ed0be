"""Reader of ``rflex-config.xml``, the RFlexServer's configuration (WURDE guide 7.6).

WURDE 7.6: the file "specifies the RFlex serial device, the type of robot being controlled, and
whether the module should be allowed to reset the brake". The guide leaves the example out
("Insert Example Here"), so the format follows its sibling ``laser-config`` (7.5)::

    <rflex-config>
      <device port="/dev/ttyS0" name="base" type="B21r" brake-reset="true"
              command-timeout="1.0"/>
    </rflex-config>

- ``port``, ``name``, ``type`` (``B21r`` or ``ATRVJr``) are required;
- ``brake-reset`` (true/false, default false): may the module release the brake;
- ``command-timeout`` (seconds > 0, default 1.0): the base is stopped when no velocity command
  came for that long.

Names are unique; the module picks its device by its own name (``-n``), as the SICK server does.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence

from .errors import ConfigError
from .rflex_robots import ROBOTS, RobotParams
from .xml_config import Attributes, children, read_root

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


def load_rflex_config(path: str | os.PathLike[str]) -> list[RFlexDevice]:
    """The devices of ``path``.

    :raises ConfigError: with file and line for a malformed file, an unknown element or attribute,
        a missing or bad attribute, no device at all, or a name used twice.
    """
    root = read_root(path, ROOT_TAG)
    devices: list[RFlexDevice] = []
    for node in children(path, root, ('device',)):
        attrs = Attributes(path, node, required=('port', 'name', 'type'),
                           optional=('brake-reset', 'command-timeout'))
        device = RFlexDevice(
            port=attrs.text('port'), name=attrs.text('name'),
            type=attrs.choice('type', tuple(ROBOTS)),
            brake_reset=attrs.boolean('brake-reset', False),
            command_timeout=attrs.number('command-timeout', 1.0, minimum=0.001),
            path=os.fspath(path), line=node.sourceline)
        clash = next((d for d in devices if d.name == device.name), None)
        if clash is not None:
            raise attrs.error(f'device name "{device.name}" is already used on line {clash.line}')
        devices.append(device)
    if not devices:
        raise ConfigError(path, root.sourceline, f'<{ROOT_TAG}> has no <device>')
    return devices


def device_named(devices: Sequence[RFlexDevice], name: str) -> RFlexDevice:
    """The device called ``name``.

    :raises ConfigError: naming the file and the names there are, when none is called ``name``.
    """
    for device in devices:
        if device.name == name:
            return device
    path = devices[0].path if devices else '<rflex-config>'
    known = ', '.join(d.name for d in devices) or 'none'
    raise ConfigError(path, None, f'no rFLEX device named "{name}" (devices: {known})')
