"""Conversions between message fields and the values a WURDE program sees.

One :class:`FieldSpec` per interface member, built from the installed interface description.
Scalars pass through (coerced, so ``set_value(8)`` works on a Double); arrays of numbers are the
message's own array (``data.ranges.append(1.0)`` writes into the event); geometry types are
write-through views (:mod:`wurde_core.geometry`); enumerations are Python enums; types defined in
an interface file are their ROS messages.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, MutableSequence
from dataclasses import dataclass
from typing import Any

from wurde_idl.types import SCALARS

from .enums import ENUMS
from .geometry import GEOMETRY

_COERCE: dict[str, Callable[[Any], Any]] = {
    'Byte': int, 'Integer': int, 'Long': int, 'Float': float, 'Double': float, 'Bool': bool,
    'String': str,
}


class SequenceView(MutableSequence):
    """A list of messages seen through a converter (geometry views, enums): writes go through."""

    def __init__(self, items: list[Any], wrap: Callable[[Any], Any],
                 unwrap: Callable[[Any], Any]) -> None:
        """A view over ``items``, which it changes in place.

        :param items: the message's list of element messages.
        :param wrap: element message -> what the program sees.
        :param unwrap: what the program gives -> element message.
        """
        self._items, self._wrap, self._unwrap = items, wrap, unwrap

    def __len__(self) -> int:
        return len(self._items)

    def __getitem__(self, index: Any) -> Any:
        if isinstance(index, slice):
            return [self._wrap(item) for item in self._items[index]]
        return self._wrap(self._items[index])

    def __setitem__(self, index: Any, value: Any) -> None:
        if isinstance(index, slice):
            self._items[index] = [self._unwrap(v) for v in value]
        else:
            self._items[index] = self._unwrap(value)

    def __delitem__(self, index: Any) -> None:
        del self._items[index]

    def insert(self, index: int, value: Any) -> None:
        """Insert ``value`` before ``index`` (``append`` and ``extend`` use it).

        :param index: the position, as for ``list.insert``.
        :param value: a view or enum (or an element message), unwrapped into the list.
        """
        self._items.insert(index, self._unwrap(value))

    def __eq__(self, other: object) -> bool:
        return list(self) == list(other) if isinstance(other, Iterable) else NotImplemented

    def __repr__(self) -> str:
        return repr(list(self))


@dataclass(frozen=True)
class FieldSpec:
    """How one member is read from and written to its message."""

    name: str
    wurde_type: str
    is_array: bool
    get: Callable[[Any], Any]
    set: Callable[[Any, Any], None]


def _element_codec(wurde_type: str, element_type: type | None
                   ) -> tuple[Callable[[Any], Any], Callable[[Any], Any]]:
    if wurde_type in GEOMETRY:
        view = GEOMETRY[wurde_type]
        return view.wrap, lambda v: v.to_msg() if hasattr(v, 'to_msg') else v
    if wurde_type in ENUMS:
        enum_type = ENUMS[wurde_type]

        def wrap_enum(m: Any) -> Any:
            return enum_type(m.value)

        def unwrap_enum(v: Any) -> Any:
            message = element_type()  # type: ignore[misc]
            message.value = int(v)
            return message
        return wrap_enum, unwrap_enum
    coerce = _COERCE.get(wurde_type)
    if coerce is not None:
        return (lambda v: v), coerce
    return (lambda v: v), (lambda v: v)


def field_spec(member: dict[str, Any], message_type: type) -> FieldSpec:
    """The :class:`FieldSpec` of one member of ``message_type`` (from its description).

    :param member: the member's entry of the installed description (``name``, ``type``,
        ``is_array``).
    :param message_type: the ROS message class holding the member.
    """
    name, wurde_type, is_array = member['name'], member['type'], member['is_array']
    element_type = None
    if wurde_type in ENUMS or wurde_type in GEOMETRY:
        element_type = type(getattr(message_type(), name)) if not is_array else None
        if is_array:
            from wurde_interfaces import msg as builtin_msgs
            element_type = getattr(builtin_msgs, wurde_type)
    wrap, unwrap = _element_codec(wurde_type, element_type)

    if is_array:
        if wurde_type in SCALARS:
            def get_array(m: Any) -> Any:
                return getattr(m, name)

            def set_array(m: Any, value: Any) -> None:
                setattr(m, name, [unwrap(v) for v in value])
            return FieldSpec(name, wurde_type, True, get_array, set_array)

        def get_view(m: Any) -> Any:
            if wurde_type in GEOMETRY or wurde_type in ENUMS:
                return SequenceView(getattr(m, name), wrap, unwrap)
            return getattr(m, name)

        def set_list(m: Any, value: Any) -> None:
            setattr(m, name, [unwrap(v) for v in value])
        return FieldSpec(name, wurde_type, True, get_view, set_list)

    if wurde_type in ENUMS:
        enum_type = ENUMS[wurde_type]

        def get_enum(m: Any) -> Any:
            return enum_type(getattr(m, name).value)

        def set_enum(m: Any, value: Any) -> None:
            getattr(m, name).value = int(value)
        return FieldSpec(name, wurde_type, False, get_enum, set_enum)

    if wurde_type in GEOMETRY:
        def get_view_one(m: Any) -> Any:
            return wrap(getattr(m, name))

        def set_geometry(m: Any, value: Any) -> None:
            setattr(m, name, unwrap(value))
        return FieldSpec(name, wurde_type, False, get_view_one, set_geometry)

    def get_plain(m: Any) -> Any:
        return getattr(m, name)

    def set_plain(m: Any, value: Any) -> None:
        setattr(m, name, unwrap(value))
    return FieldSpec(name, wurde_type, False, get_plain, set_plain)
