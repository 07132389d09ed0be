"""Reading the drivers' XML files (device configs, maps): attributes checked, errors with file:line.

Every file goes through the suite's hardened parser (``wurde_idl.safe_xml``). Unknown tags and
attributes are refused by name, as launch_xml does (docs/style.md), so a typo never passes silently: the
element and attribute checks (:class:`Attributes`, :func:`children`, :func:`local_name`) are
:mod:`wurde_idl.xml_elements`, shared with the map format (:mod:`wurde_idl.mapfile`); this module
adds what only device configs have (``<device name=...>`` lists).
Pure Python: usable from codecs' neighbours and the simulated world alike.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Protocol, TypeVar

from lxml import etree
from wurde_idl.errors import ConfigError
from wurde_idl.safe_xml import parse_file
from wurde_idl.xml_elements import Attributes, children, local_name

__all__ = ['Attributes', 'children', 'device_named', 'local_name', 'read_devices', 'read_root']


def read_root(path: str | os.PathLike[str], root_tag: str | tuple[str, ...]) -> etree._Element:
    """Parse ``path`` with the hardened parser.

    :param path: the XML file.
    :param root_tag: the root element's name, or the names it may have.
    :raises ConfigError: with file, line and reason.
    """
    return parse_file(path, root_tag=root_tag)


class _Named(Protocol):
    # Read-only members: the devices are frozen dataclasses.
    @property
    def name(self) -> str: ...

    @property
    def path(self) -> str: ...

    @property
    def line(self) -> int | None: ...


Device = TypeVar('Device', bound=_Named)


def read_devices(path: str | os.PathLike[str], root_tag: str,
                 parse: Callable[[str, etree._Element], Device]) -> list[Device]:
    """The ``<device>`` elements of a device config (``<laser-config>``, ``<rflex-config>``, ...).

    Every device file of WURDE's drivers has this shape (guide 7.5): a root holding one or more
    ``<device name=...>``.

    :param path: the config file.
    :param root_tag: its root element's name.
    :param parse: ``parse(path, node)`` reads one ``<device>``.
    :raises ConfigError: duplicate names or no device, naming the file and the line.
    """
    path = os.fspath(path)
    root = read_root(path, root_tag)
    devices: list[Device] = []
    for node in children(path, root, ('device',)):
        device = parse(path, node)
        clash = next((d for d in devices if d.name == device.name), None)
        if clash is not None:
            raise ConfigError(path, node.sourceline, f'duplicate device name "{device.name}" '
                                                     f'(first on line {clash.line})')
        devices.append(device)
    if not devices:
        raise ConfigError(path, root.sourceline, f'<{root_tag}> holds no <device>')
    return devices


def device_named(devices: Sequence[Device], name: str, *, path: str | os.PathLike[str] = '') -> Device:
    """The device called ``name`` — a module picks its device by its ``-n`` name (WURDE 7.5).

    :param devices: the file's devices.
    :param name: the module's name.
    :param path: the file, named in the error when ``devices`` is empty.
    :raises ConfigError: no device has that name; names the file and the names it does have.
    """
    for device in devices:
        if device.name == name:
            return device
    where = devices[0].path if devices else os.fspath(path)
    names = ', '.join(device.name for device in devices) or 'none'
    raise ConfigError(where, None, f'no <device> named "{name}" (devices: {names})')
