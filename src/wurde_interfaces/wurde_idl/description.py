"""Run-time descriptions of interfaces, installed under ``share/<package>/wurde/interfaces/``.

The generator writes one JSON file per interface; packages that define interfaces register
themselves in the ament index under the resource type :data:`RESOURCE_TYPE`, so that
:func:`load_all` finds every interface of every installed package without importing them.
``wurde_core`` builds its RobotObject classes from these descriptions.
"""

from __future__ import annotations

import functools
import json
import os
import pathlib
from dataclasses import asdict
from typing import Any

from .errors import UnknownInterfaceError
from .model import Interface, Member

#: ament index resource type listing the interfaces a package defines (one name per line).
RESOURCE_TYPE = 'wurde_interfaces'
FORMAT_VERSION = 1


def to_json(interface: Interface, package: str) -> dict[str, Any]:
    """The description of ``interface`` as a JSON-ready dict (what :func:`load` returns).

    :param interface: a validated interface.
    :param package: the ROS package its messages belong to.
    """
    def section(members: tuple[Member, ...] | None) -> list[dict[str, Any]] | None:
        if members is None:
            return None
        return [{k: v for k, v in asdict(m).items() if k != 'line'} for m in members]

    return {
        'format': FORMAT_VERSION,
        'package': package,
        'name': interface.name,
        'version': interface.version,
        'author': interface.author,
        'description': interface.description,
        'source_file': os.path.basename(interface.path),
        'data_message': interface.data_message,
        'info_message': interface.info_message,
        'types': {t.name: section(t.members) for t in interface.types},
        'info': section(interface.info),
        'publish': section(interface.publish),
        'dropped_count_members': {k: list(v) for k, v in interface.dropped.items()},
    }


def _prefixes() -> list[pathlib.Path]:
    return [pathlib.Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]


def load_all() -> dict[str, dict[str, Any]]:
    """Every installed interface description, by interface name (first prefix wins).

    Read once per value of ``AMENT_PREFIX_PATH`` and process (a sourced workspace changes the
    value, and with it what is found); treat the result as read-only.
    """
    return _load_all(os.environ.get('AMENT_PREFIX_PATH', ''))


@functools.lru_cache(maxsize=8)
def _load_all(_prefix_path: str) -> dict[str, dict[str, Any]]:
    found: dict[str, dict[str, Any]] = {}
    for prefix in _prefixes():
        index = prefix / 'share' / 'ament_index' / 'resource_index' / RESOURCE_TYPE
        if not index.is_dir():
            continue
        for marker in sorted(index.iterdir()):
            package = marker.name
            for name in marker.read_text().split():
                path = prefix / 'share' / package / 'wurde' / 'interfaces' / f'{name}.json'
                if name not in found and path.is_file():
                    found[name] = json.loads(path.read_text())
    return found


def load(name: str) -> dict[str, Any]:
    """The description of interface ``name``.

    :param name: the interface's name (``Foo``).
    :raises UnknownInterfaceError: when no installed package defines it; the message lists the
        interfaces that are installed.
    """
    everything = load_all()
    try:
        return everything[name]
    except KeyError:
        known = ', '.join(sorted(everything)) or 'none (is the workspace sourced?)'
        raise UnknownInterfaceError(f'unknown interface "{name}"; installed: {known}') from None
