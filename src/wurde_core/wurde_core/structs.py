"""The ``data``, ``info`` and ``requests`` structures of a RobotObject.

Each is a thin view over the ROS message of the current event: a received event is adopted as it
is (no copy), and the program's writes go straight into the message that will be published.
``data`` members are plain attributes (``foo.data.ranges``); ``info`` and ``requests`` members are
:class:`~wurde_core.writable.Writable` values (``foo.info.max_range.set_value(8.0)``), as in the
guide.  Both also have ``timestamp`` (a :class:`~wurde_core.timestamp.Timestamp`) and ``source``.
"""

from __future__ import annotations

from typing import Any

from .errors import MemberError
from .fields import FieldSpec
from .timestamp import Timestamp
from .writable import Writable


class _Struct:
    """Common part: the message, its header accessors, and reset to a fresh message."""

    _fields: dict[str, FieldSpec] = {}
    _message_type: type
    _msg: Any  # the current event's message, set with object.__setattr__

    def __init__(self, message: Any = None) -> None:
        object.__setattr__(self, '_msg', message if message is not None else self._message_type())

    @property
    def timestamp(self) -> Timestamp:
        """When the event was published (auto-timestamp) or set by the program."""
        return Timestamp.from_msg(self._msg.header.stamp)

    @timestamp.setter
    def timestamp(self, value: Timestamp) -> None:
        value.to_msg(self._msg.header.stamp)

    @property
    def source(self) -> str:
        """Who published the event (auto-tag: the module's name)."""
        return self._msg.header.source

    @source.setter
    def source(self, value: str) -> None:
        self._msg.header.source = value

    def ros_message(self) -> Any:
        """The ROS message behind this structure (shared, not a copy)."""
        return self._msg

    def _adopt(self, message: Any) -> None:
        """Make ``message`` (a received event) the current one."""
        object.__setattr__(self, '_msg', message)

    def field_names(self) -> list[str]:
        """Member names, in interface order."""
        return list(self._fields)


class DataStruct(_Struct):
    """``obj.data``: members as attributes."""

    def __getattr__(self, name: str) -> Any:
        spec = type(self)._fields.get(name)
        if spec is None:
            raise _no_member(self, name)
        return spec.get(self._msg)

    def __setattr__(self, name: str, value: Any) -> None:
        spec = type(self)._fields.get(name)
        if spec is None:
            if not isinstance(getattr(type(self), name, None), property):
                raise _no_member(self, name)  # a typo must not pass silently
            object.__setattr__(self, name, value)  # properties (timestamp, source)
            return
        spec.set(self._msg, value)

    def __repr__(self) -> str:
        values = ', '.join(f'{n}={getattr(self, n)!r}' for n in self._fields)
        return f'{type(self).__name__}({values})'


class InfoStruct(_Struct):
    """``obj.info`` and ``obj.requests``: members are Writable values with locks."""

    def __init__(self, message: Any = None, *, owner: Any = None, channel: str = 'info') -> None:
        """A structure over ``message``.

        :param message: the Info message; None: a fresh one.
        :param owner: the RobotObject holding it, whose locks and direction writes obey; None:
            no checks.
        :param channel: ``info`` or ``requests``, which the object's checks tell apart.
        """
        super().__init__(message)
        object.__setattr__(self, '_owner', owner)
        object.__setattr__(self, '_channel', channel)
        object.__setattr__(self, '_written_fields', set())
        object.__setattr__(self, '_writables', {})

    def __getattr__(self, name: str) -> 'Writable':
        writables = self.__dict__['_writables']
        if name in writables:
            return writables[name]
        spec = type(self)._fields.get(name)
        if spec is None:
            raise _no_member(self, name)
        writable = Writable(self, spec)
        writables[name] = writable
        return writable

    def __setattr__(self, name: str, value: Any) -> None:
        if name in type(self)._fields:
            raise MemberError(f'use {self._channel}.{name}.set_value(...) to change {name!r} '
                              '(info and request members are Writable)')
        if not isinstance(getattr(type(self), name, None), property):
            raise _no_member(self, name)
        object.__setattr__(self, name, value)

    def _written(self) -> set[str]:
        """Members set with ``set_value`` since the last publish."""
        return self.__dict__['_written_fields']

    def __repr__(self) -> str:
        values = ', '.join(f'{n}={self._fields[n].get(self._msg)!r}' for n in self._fields)
        return f'{type(self).__name__}({values})'


def _no_member(struct: _Struct, name: str) -> MemberError:
    return MemberError(f'{type(struct).__name__} has no member {name!r}; members: '
                       f'{", ".join(struct._fields) or "none"}')


def struct_class(base: type[_Struct], name: str, message_type: type,
                 fields: dict[str, FieldSpec]) -> type[_Struct]:
    """A :class:`DataStruct` or :class:`InfoStruct` subclass for one message type.

    :param base: DataStruct or InfoStruct.
    :param name: the class's name (``FooData``).
    :param message_type: the ROS message class.
    :param fields: the members' specs, by name, in interface order.
    """
    return type(name, (base,), {'_fields': fields, '_message_type': message_type})


def write_members(target: Any, values: dict[str, Any]) -> None:
    """Set members of a ``data`` struct (plain attributes) or of ``info``/``requests``
    (Writable members, whose ``set_value`` checks locks) alike, by name.

    :param target: ``obj.data``, ``obj.info`` or ``obj.requests``.
    :param values: member name -> new value.
    :raises MemberError: for a name the interface does not have.
    """
    for name, item in values.items():
        member = getattr(target, name)
        if hasattr(member, 'set_value'):
            member.set_value(item)
        else:
            setattr(target, name, item)
