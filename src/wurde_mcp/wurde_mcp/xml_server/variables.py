"""The xmlServer's variable pool: what the socket protocol reads and writes, apart from where the
values come from.

AU Robot Servers, "Interface description" / "Value exchange": a variable has a dotted name
(``odoPose.pose``: structure ``odoPose``, variable ``pose``; names are not case sensitive), a type
``typ`` — ``d`` (one or more doubles), ``pose`` (x, y, th), ``m2`` (a matrix of doubles, rows
separated by ``;``) or ``s`` (a string) — and a ``size`` (characters of a string, doubles of the
rest).  The server (:mod:`.server`) knows only this module's :class:`VariablePool`; the pool of the
running robot (:mod:`.robot_table`) fills it from the WURDE streams.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import Union

__all__ = ['TYPES', 'Value', 'VarError', 'Variable', 'VariablePool', 'format_value', 'parse_value']

#: The seed's typ codes.
TYPES = ('d', 'pose', 'm2', 's')

#: A value: doubles (``d``, ``pose``: x, y, th and optionally a time), rows of doubles (``m2``) or text.
Value = Union[list[float], list[list[float]], str]


class VarError(Exception):
    """A variable operation that cannot be done; ``str()`` is the warning the client is sent."""


def _number(x: float) -> str:
    """C-locale text of a double, as short as keeps it exact to 1e-9 relative — and to the
    microsecond from 1e6 to 1e12, where 10 digits would round a time stamp (the seed's
    ``1286376207.8752``) to the second."""
    if math.isnan(x) or math.isinf(x):
        return repr(x).lower()
    if 1e6 <= abs(x) < 1e12:
        return f'{x:.6f}'.rstrip('0').rstrip('.')
    return f'{x:.10g}'


def format_value(typ: str, value: Value) -> tuple[str, int]:
    """The ``value`` attribute's text and the ``size`` attribute of a value of type ``typ``.

    :param typ: one of :data:`TYPES`.
    :param value: a value of that type (a string for ``s``, rows for ``m2``, else doubles).
    :returns: the text (numbers in the C locale, ``m2`` rows joined by ``;``) and the size
        (characters of a string, doubles of the rest).
    """
    if typ == 's':
        assert isinstance(value, str)
        return value, len(value)
    if typ == 'm2':
        rows = [[float(v) for v in row] for row in value]          # type: ignore[union-attr]
        return '; '.join(' '.join(_number(v) for v in row) for row in rows), sum(len(r) for r in rows)
    numbers = [float(v) for v in value]                             # type: ignore[arg-type]
    return ' '.join(_number(v) for v in numbers), len(numbers)


def parse_value(typ: str, text: str) -> Value:
    """The value of type ``typ`` written as ``text`` by a client (``var X="..."``).

    :param typ: one of :data:`TYPES`.
    :param text: the client's text: doubles separated by spaces or commas, ``m2`` rows of equal
        length separated by ``;``, or any text for ``s``.
    :raises VarError: the text is not a value of that type.
    """
    if typ == 's':
        return text
    try:
        if typ == 'm2':
            rows = [[float(v) for v in row.split()] for row in text.split(';') if row.strip()]
            if len({len(r) for r in rows}) > 1:
                raise VarError(f'rows of unequal length in "{text}"')
            return rows
        return [float(v) for v in text.replace(',', ' ').split()]
    except ValueError:
        raise VarError(f'"{text}" is not a value of type {typ}') from None


@dataclasses.dataclass
class Variable:
    """One variable of the pool."""

    #: Full dotted name as the pool spells it (``odoPose.pose``).
    name: str
    #: One of :data:`TYPES`.
    typ: str
    #: What ``var desc`` prints: what it is, (r) or (r/w), units.
    description: str
    #: The current value (read with :attr:`read` when set, else this).
    value: Value = dataclasses.field(default_factory=list)
    #: Called to write a new value (already parsed); None: read-only.  May raise VarError (a
    #: refusal, e.g. a Writable lock) — the old value is kept.
    write: Callable[[Value], None] | None = None
    #: Called to read the current value, when the value lives elsewhere (None: :attr:`value`).
    read: Callable[[], Value] | None = None

    @property
    def writable(self) -> bool:
        return self.write is not None

    def current(self) -> Value:
        return self.read() if self.read is not None else self.value


class VariablePool:
    """Variables by case-insensitive dotted name; structures are the dotted prefixes.

    Each structure counts its updates (:meth:`touch`), which an event push (``varpush``) watches.
    """

    def __init__(self) -> None:
        self._vars: dict[str, Variable] = {}
        self._updates: dict[str, int] = {}
        self._descriptions: dict[str, str] = {}

    def add(self, variable: Variable) -> Variable:
        """Add a variable (replacing one of the same name, in any case).

        :param variable: the variable; its ``typ`` must be one of :data:`TYPES`.
        :returns: ``variable``.
        :raises ValueError: for another ``typ``.
        """
        if variable.typ not in TYPES:
            raise ValueError(f'{variable.name}: typ {variable.typ!r} is not one of {TYPES}')
        self._vars[variable.name.lower()] = variable
        return variable

    def describe(self, struct: str, description: str) -> None:
        """Set the description of a structure (``var list`` shows it).

        :param struct: the structure's dotted name ('' the root), any case.
        :param description: the text.
        """
        self._descriptions[struct.lower()] = description

    def find(self, name: str) -> Variable | None:
        """The variable ``name`` (any case), or None.

        :param name: a variable's full dotted name.
        """
        return self._vars.get(name.lower())

    def is_struct(self, name: str) -> bool:
        """Whether ``name`` (any case) is a structure: a prefix of some variable's name."""
        prefix = name.lower().rstrip('.') + '.'
        return name.strip('.') == '' or any(key.startswith(prefix) for key in self._vars)

    def struct_name(self, name: str) -> str:
        """``name`` of a structure spelled as the pool spells it (``odopose`` -> ``odoPose``)."""
        depth = name.strip('.').count('.') + 1
        prefix = name.lower().strip('.') + '.'
        for key, var in self._vars.items():
            if key.startswith(prefix):
                return '.'.join(var.name.split('.')[:depth])
        return name

    def children(self, struct: str = '') -> list[tuple[str, bool]]:
        """The direct members of ``struct`` ('' the root): (name as spelled, is a structure)."""
        prefix = struct.lower().strip('.')
        prefix = prefix + '.' if prefix else ''
        seen: dict[str, tuple[str, bool]] = {}
        for key, var in self._vars.items():
            if not key.startswith(prefix):
                continue
            parts = var.name.split('.')[prefix.count('.'):]
            seen.setdefault(parts[0].lower(), (parts[0], len(parts) > 1))
        return sorted(seen.values(), key=lambda item: item[0].lower())

    def variables(self, struct: str = '') -> list[Variable]:
        """Every variable in ``struct`` and its sub-structures ('' every one), sorted by name."""
        prefix = struct.lower().strip('.')
        prefix = prefix + '.' if prefix else ''
        return sorted((v for k, v in self._vars.items() if k.startswith(prefix)),
                      key=lambda v: v.name.lower())

    def description(self, struct: str) -> str:
        return self._descriptions.get(struct.lower().strip('.'), '')

    def set(self, name: str, text: str) -> tuple[Value, Value]:
        """Write ``text`` to variable ``name``: (old value, new value).

        :param name: a variable's full dotted name, any case.
        :param text: the client's text of the value (:func:`parse_value`); a pose needs x y th.
        :raises VarError: no such variable, read-only, a value of the wrong type or the owner refused.
        """
        var = self.find(name)
        if var is None:
            raise VarError('not found - try: var help')
        if var.write is None:
            raise VarError(f'{var.name} is read-only')
        new = parse_value(var.typ, text)
        if var.typ == 'pose' and len(new) < 3:
            raise VarError(f'a pose is x y th, got "{text}"')
        old = var.current()
        var.write(new)
        if var.read is None:
            var.value = new
        self.touch(var.name)
        return old, var.current()

    def touch(self, name: str) -> None:
        """Count an update of variable or structure ``name`` and of every structure above it."""
        parts = name.lower().split('.')
        for depth in range(1, len(parts) + 1):
            key = '.'.join(parts[:depth])
            self._updates[key] = self._updates.get(key, 0) + 1

    def updates(self, name: str) -> int:
        """How often ``name`` (a variable or structure, any case) was updated so far."""
        return self._updates.get(name.lower().strip('.'), 0)

    def update(self, name: str, value: Value) -> None:
        """Store a new value of the variable ``name`` from its source and count the update.

        :param name: a variable's full dotted name, any case.
        :param value: the new value, of the variable's type (not checked).
        :raises KeyError: no such variable.
        """
        var = self.find(name)
        if var is None:
            raise KeyError(name)
        var.value = value
        self.touch(var.name)

    def names(self) -> Sequence[str]:
        return [v.name for v in self.variables()]
