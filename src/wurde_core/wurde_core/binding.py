"""Bind a RobotObject class to its interface: message types and data/info structures.

The description comes from what ``wurde_interfaces`` (or any package that calls
``wurde_generate_interfaces``) installed; it is read once per interface and process.  Binding
happens when a class is first used, never at import time, so ``import wurde_core`` works before
any workspace is sourced.
"""

from __future__ import annotations

import importlib
from typing import Any

from wurde_idl import load

from .fields import field_spec
from .structs import DataStruct, InfoStruct, struct_class


def _message_type(package: str, name: str) -> type:
    return getattr(importlib.import_module(f'{package}.msg'), name)


def bind(cls: Any, interface: str) -> None:
    """Give ``cls`` the message types and structures of ``interface``.

    :param cls: a RobotObject class; its ``description``, ``data_type``, ``info_type`` and
        structures are set.
    :param interface: the interface's name (``Foo``).
    :raises UnknownInterfaceError: when no installed package defines ``interface``.
    """
    desc = load(interface)
    data_type = _message_type(desc['package'], desc['data_message'])
    info_type = _message_type(desc['package'], desc['info_message'])
    data_fields = {m['name']: field_spec(m, data_type) for m in desc['publish'] or []}
    info_fields = {m['name']: field_spec(m, info_type) for m in desc['info'] or []}
    cls.description = desc
    cls.data_type = data_type
    cls.info_type = info_type
    cls._data_struct = struct_class(DataStruct, f'{interface}Data', data_type, data_fields)
    cls._info_struct = struct_class(InfoStruct, f'{interface}Info', info_type, info_fields)
    cls._bound_interface = interface
