"""One RobotObject class per installed interface: ``from wurde_core.interfaces import Foo``.

Classes are built on first use from the descriptions that ``wurde_interfaces`` (and any package
that calls ``wurde_generate_interfaces``) installs, so a user-defined interface is imported the
same way as a built-in one.  The guide's special wrappers (ObstacleAvoider, VectorMover) and the
Logger are importable from here too.
"""

from __future__ import annotations

import importlib
from typing import Any

from wurde_idl import load, load_all

from .fields import field_spec
from .robot_object import RobotObject
from .structs import DataStruct, InfoStruct, struct_class

_classes: dict[str, type[RobotObject]] = {}
_WRAPPERS = {'ObstacleAvoider': 'wurde_core.wrappers', 'VectorMover': 'wurde_core.wrappers',
             'Logger': 'wurde_core.logger'}


def _message_type(package: str, name: str) -> type:
    return getattr(importlib.import_module(f'{package}.msg'), name)


def robot_object_class(name: str) -> type[RobotObject]:
    """The RobotObject class of interface ``name``.

    :raises UnknownInterfaceError: when no installed package defines it.
    """
    cls = _classes.get(name)
    if cls is not None:
        return cls
    desc = load(name)
    data_type = _message_type(desc['package'], desc['data_message'])
    info_type = _message_type(desc['package'], desc['info_message'])
    data_fields = {m['name']: field_spec(m, data_type) for m in desc['publish'] or []}
    info_fields = {m['name']: field_spec(m, info_type) for m in desc['info'] or []}
    cls = type(name, (RobotObject,), {
        '__doc__': f'RobotObject of interface {name} {desc["version"]}.\n\n{desc["description"]}',
        '__module__': __name__,
        'interface_name': name,
        'description': desc,
        'data_type': data_type,
        'info_type': info_type,
        '_data_struct': struct_class(DataStruct, f'{name}Data', data_type, data_fields),
        '_info_struct': struct_class(InfoStruct, f'{name}Info', info_type, info_fields),
    })
    _classes[name] = cls
    return cls


def __getattr__(name: str) -> Any:
    if name in _WRAPPERS:
        return getattr(importlib.import_module(_WRAPPERS[name]), name)
    if name.startswith('_'):
        raise AttributeError(name)
    return robot_object_class(name)


def __dir__() -> list[str]:
    return sorted(set(load_all()) | set(_WRAPPERS) | {'robot_object_class'})
