"""Message type names as bags spell them, and their Python classes.

rosbag2 writes ``pkg/msg/Name``; bags of older tools also ``pkg/Name`` (rosbag2's own test bags
do), and service events are ``pkg/srv/Name_Event``.  A name comes from a file, so it is checked
to be three identifiers before anything is imported by it.
"""

from __future__ import annotations

import importlib
from typing import Any

from .errors import MessageTypeError

__all__ = ['message_class', 'normalize_type']

_KINDS = ('msg', 'srv', 'action')


def normalize_type(type_name: str) -> str:
    """``pkg/Name`` -> ``pkg/msg/Name``; any other name as it is.

    :param type_name: a ROS type name.
    """
    parts = type_name.split('/')
    return f'{parts[0]}/msg/{parts[1]}' if len(parts) == 2 else type_name


def message_class(type_name: str) -> Any:
    """The Python class of ``pkg/msg/Name`` (or ``pkg/Name``, ``pkg/srv/Name_Event``...).

    :param type_name: the type's name; its package is imported.
    :raises MessageTypeError: not a type name, or the type is not installed here.
    """
    parts = normalize_type(type_name).split('/')
    if len(parts) != 3 or parts[1] not in _KINDS or not all(p.isidentifier() for p in parts):
        raise MessageTypeError(f'{type_name!r} is not a message type name (pkg/msg/Name)')
    package, kind, name = parts
    try:
        module = importlib.import_module(f'{package}.{kind}')
    except ImportError as error:
        raise MessageTypeError(f'{type_name} is not installed here ({error})') from error
    cls = getattr(module, name, None)
    if cls is None or not hasattr(cls, 'get_fields_and_field_types'):
        raise MessageTypeError(f'{type_name} is not installed here (no message {name} in {package}.{kind})')
    return cls
