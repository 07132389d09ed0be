"""A message type's full definition, as rosbag2 stores it in MCAP (``ros2msg`` schema encoding):
the type's ``.msg`` text, then each type it uses, once, after a line of 80 ``=`` and
``MSG: pkg/msg/Name``."""

from __future__ import annotations

import functools
import pathlib
import re

from ament_index_python.packages import get_package_share_directory

__all__ = ['PRIMITIVES', 'message_definition']

PRIMITIVES = frozenset({'bool', 'byte', 'char', 'float32', 'float64', 'int8', 'uint8', 'int16', 'uint16',
                        'int32', 'uint32', 'int64', 'uint64', 'string', 'wstring'})
_SEPARATOR = '=' * 80
_BOUND = re.compile(r'(<=\d+)?(\[[^\]]*\])?$')


def _split(type_name: str) -> tuple[str, str]:
    """``pkg/msg/Name`` or ``pkg/Name`` -> (pkg, Name)."""
    parts = type_name.split('/')
    if len(parts) not in (2, 3) or (len(parts) == 3 and parts[1] != 'msg'):
        raise ValueError(f'{type_name!r} is not a message type name (pkg/msg/Name)')
    return parts[0], parts[-1]


@functools.lru_cache(maxsize=None)
def _text(package: str, name: str) -> str:
    path = pathlib.Path(get_package_share_directory(package)) / 'msg' / f'{name}.msg'
    return path.read_text()


def _used(package: str, text: str) -> list[tuple[str, str]]:
    """The message types the fields of ``text`` use (constants and primitives left out)."""
    used = []
    for line in text.splitlines():
        line = line.split('#', 1)[0].strip()
        if not line:
            continue
        base = _BOUND.sub('', line.split()[0])
        if base in PRIMITIVES:
            continue
        parts = base.split('/')
        used.append((package, parts[0]) if len(parts) == 1 else (parts[0], parts[-1]))
    return used


def message_definition(type_name: str) -> str:
    """The full ``ros2msg`` definition of ``type_name`` (``pkg/msg/Name``) with its dependencies.

    :raises ValueError: not a message type name.
    :raises OSError: the package or its ``.msg`` file is not installed.
    """
    package, name = _split(type_name)
    sections = [_text(package, name).rstrip('\n')]
    seen = {(package, name)}
    todo = _used(package, sections[0])
    while todo:
        dep = todo.pop(0)
        if dep in seen:
            continue
        seen.add(dep)
        text = _text(*dep).rstrip('\n')
        sections.append(f'{_SEPARATOR}\nMSG: {dep[0]}/msg/{dep[1]}\n{text}')
        todo.extend(_used(dep[0], text))
    return '\n'.join(sections) + '\n'
