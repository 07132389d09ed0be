"""Identifier rules: WURDE names in, valid ROS 2 names out.

WURDE's C++ interfaces used camelCase members (``maxRange``, ``transLimit``); ROS 2 fields must be
snake_case.  The rule is one function, :func:`field_name`: an underscore goes before each capital
that follows a lower-case letter or digit, and before the last capital of a run of capitals that is
followed by a lower-case letter; then everything is lower-cased (``maxRange`` -> ``max_range``,
``TTL`` -> ``ttl``, ``PTUnitSpeed`` -> ``pt_unit_speed``).  Names already in snake_case are
unchanged.  The interface description keeps both spellings.
"""

from __future__ import annotations

import keyword
import re

_IDENTIFIER = re.compile(r'^[A-Za-z][A-Za-z0-9_]*$')
_ROS_FIELD = re.compile(r'^[a-z][a-z0-9]*(_[a-z0-9]+)*$')
_TYPE_NAME = re.compile(r'^[A-Z][A-Za-z0-9]*$')
_CAMEL_1 = re.compile(r'(?<=[a-z0-9])([A-Z])')
_CAMEL_2 = re.compile(r'(?<=[A-Z])([A-Z])(?=[a-z])')

#: Names members may not use: fields every generated Data/Info message already has, and the
#: accessors wurde_core puts beside the members (``obj.data.timestamp``, ``obj.data.ros_message()``).
RESERVED_FIELDS = frozenset({'header', 'set_fields', 'locks', 'source', 'timestamp',
                             'ros_message', 'field_names'})


def field_name(name: str) -> str:
    """Map a WURDE member name to its ROS 2 field name (see the module docstring).

    :param name: the member's name as the interface file writes it (``maxRange``).
    """
    return _CAMEL_2.sub(r'_\1', _CAMEL_1.sub(r'_\1', name)).lower()


def check_member_name(name: str) -> str | None:
    """Return why ``name`` cannot be a member name, or ``None`` when it can.

    :param name: the member's name as the interface file writes it; its ROS field name must be
        valid snake_case, not reserved (:data:`RESERVED_FIELDS`) and not a Python keyword.
    """
    if not _IDENTIFIER.match(name):
        return 'must start with a letter and contain only letters, digits and underscores'
    ros = field_name(name)
    if not _ROS_FIELD.match(ros):
        return (f'becomes ROS field "{ros}", which is not valid (no double, leading or '
                'trailing underscores)')
    if ros in RESERVED_FIELDS:
        return f'"{ros}" is reserved for the common header of every message'
    if keyword.iskeyword(ros) or ros in ('self', 'cls', 'async', 'await'):
        return f'"{ros}" is a Python keyword'
    return None


def check_type_name(name: str) -> str | None:
    """Return why ``name`` cannot name an interface or a type, or ``None`` when it can.

    :param name: the interface's or ``<type>``'s name; it must be PascalCase.
    """
    if not _TYPE_NAME.match(name):
        return 'must be PascalCase: a capital letter, then only letters and digits'
    return None
