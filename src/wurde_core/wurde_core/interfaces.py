"""One RobotObject class per installed interface: ``from wurde_core.interfaces import Foo``.

Classes are made on first use from the descriptions that ``wurde_interfaces`` (and any package
that calls ``wurde_generate_interfaces``) installs, so a user-defined interface is imported the
same way as a built-in one.  The guide's special wrappers (ObstacleAvoider, VectorMover,
Navigator, ImageSource) and the Logger are importable from here too.  A name that no installed
package defines is not an attribute of this module (``hasattr`` answers False; the error lists
what is installed).
"""

from __future__ import annotations

import importlib
from typing import Any

from wurde_idl import load_all

from .errors import MemberError, UnknownInterfaceError
from .robot_object import RobotObject

_classes: dict[str, type[RobotObject]] = {}
_WRAPPERS = {'ObstacleAvoider': 'wurde_core.wrappers', 'VectorMover': 'wurde_core.wrappers',
             'Navigator': 'wurde_core.wrappers', 'ImageSource': 'wurde_core.image_source',
             'Logger': 'wurde_core.logger', 'ModuleLogger': 'wurde_core.logger'}


def robot_object_class(name: str) -> type[RobotObject]:
    """The RobotObject class of interface ``name`` (made and bound once per process).

    :param name: the interface's name (``Foo``, ``Heartbeat``).
    :raises UnknownInterfaceError: when no installed package defines it.
    """
    cls = _classes.get(name)
    if cls is not None:
        return cls
    cls = type(name, (RobotObject,), {'__module__': __name__}, interface=name)
    cls.bind_interface()
    cls.__doc__ = (f'RobotObject of interface {name} {cls.description["version"]}.\n\n'
                   f'{cls.description["description"]}')
    _classes[name] = cls
    return cls


def __getattr__(name: str) -> Any:
    if name in _WRAPPERS:
        return getattr(importlib.import_module(_WRAPPERS[name]), name)
    if name.startswith('_'):
        raise AttributeError(name)
    try:
        return robot_object_class(name)
    except UnknownInterfaceError as exc:
        raise MemberError(str(exc)) from exc


def __dir__() -> list[str]:
    return sorted(set(load_all()) | set(_WRAPPERS) | {'robot_object_class'})
