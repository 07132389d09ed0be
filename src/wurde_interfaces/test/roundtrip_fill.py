"""Deterministic contents for any generated message, shared by the round-trip test and its peer.

Values are chosen to survive the wire exactly: small integers and multiples of 1/4 (exact in
float32), short ASCII strings, two-element sequences.  The same (message type, salt) always gives
an equal message, so the receiving process can rebuild what the sender sent.
"""

from __future__ import annotations

import importlib
import zlib
from typing import Any

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

#: Reliable and transient-local: a subscriber that joins late still gets the one message.
QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                 durability=DurabilityPolicy.TRANSIENT_LOCAL)

_INTEGERS = {'int8', 'uint8', 'int16', 'uint16', 'int32', 'uint32', 'int64', 'uint64', 'octet'}
_FLOATS = {'float', 'double'}


def message_class(type_name: str) -> type:
    """``'pkg/Name'`` -> the Python message class."""
    package, name = type_name.split('/')
    return getattr(importlib.import_module(f'{package}.msg'), name)


def _number(path: str) -> int:
    return zlib.crc32(path.encode()) % 97 + 1


def _value(type_name: str, path: str) -> Any:
    if type_name.startswith('sequence<'):
        inner = type_name[len('sequence<'):-1].split(',')[0]
        return [_value(inner, f'{path}[{i}]') for i in range(2)]
    if type_name in _INTEGERS:
        return _number(path) % 100
    if type_name in _FLOATS:
        return _number(path) / 4.0
    if type_name == 'boolean':
        return _number(path) % 2 == 0
    if type_name == 'string' or type_name.startswith('string<'):
        return f'{path.rsplit(".", 1)[-1]}-{_number(path)}'
    return fill(message_class(type_name), path)


def fill(cls: type, salt: str) -> Any:
    """An instance of ``cls`` with every field (recursively) set from ``salt``."""
    message = cls()
    for field, type_name in cls.get_fields_and_field_types().items():
        if type_name == 'builtin_interfaces/Time':
            value = message_class(type_name)(sec=_number(salt + field), nanosec=123_456_000)
        else:
            value = _value(type_name, f'{salt}.{field}')
        setattr(message, field, value)
    return message


def topic(interface: str, channel: str) -> str:
    return f'/wurde_roundtrip/{interface}/{channel}'
