"""The values of CARMEN's parameters (Programming with CARMEN 6): the four types, the conversion on
demand, the parameter factory's entries and the ``-h`` table — what the client
(:mod:`wurde_core.carmen_param`) and the daemon (``wurde_mcp.carmen``) agree on, no ROS."""

from __future__ import annotations

import enum
import math
import re
from collections.abc import Callable, MutableMapping, Sequence
from dataclasses import dataclass
from typing import Any

from .errors import InvalidValueError, WurdeError

__all__ = ['Handler', 'Param', 'ParamError', 'ParamExit', 'ParamType', 'ParamTypeError', 'DaemonError',
           'Target', 'as_served', 'assign', 'convert', 'param_table', 'text_of', 'typed_value']

_INT = re.compile(r'[+-]?\d+')
_FLOAT = re.compile(r'[+-]?(\d+\.\d*|\.\d+|\d+)([eE][+-]?\d+)?')
_ONOFF = {'on': True, 'off': False}


class ParamType(enum.Enum):
    """CARMEN_PARAM_INT, _DOUBLE, _ONOFF, _STRING."""

    INT = 'int'
    DOUBLE = 'double'
    ONOFF = 'onoff'
    STRING = 'string'


class ParamError(WurdeError):
    """Root of this module's errors."""


class ParamTypeError(ParamError, ValueError):
    """A parameter's value cannot be had as the type asked for."""


class DaemonError(ParamError):
    """The daemon did not answer in time, or refused a set (its reason is in the message)."""


class ParamExit(SystemExit):
    """:meth:`CarmenParams.install_params` ends the program: ``-h`` (status 0), or a parameter
    missing or unusable (status 1); ``str()`` is the message, already printed."""

    def __init__(self, status: int, message: str) -> None:
        """The exit of :meth:`CarmenParams.install_params`.

        :param status: the exit status (0 after ``-h``, 1 for a parameter missing or unusable).
        :param message: what was printed.
        """
        super().__init__(status)
        self.message = message

    def __str__(self) -> str:
        return self.message


#: Where a value goes: ``(obj, 'attr')`` or ``(mapping, key)``.
Target = tuple[Any, str]
#: ``handler(module, variable, value)``, after the target was set.
Handler = Callable[[str, str, Any], None]


@dataclass(frozen=True)
class Param:
    """One entry of the parameter factory's list (carmen_param_t, 6.2)."""

    module: str
    variable: str
    type: ParamType | str   # a ParamType or its value ('int', 'double', 'onoff', 'string')
    target: Target | None = None
    subscribe: bool = False
    handler: Handler | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, 'type', ParamType(self.type))
        target = self.target
        if target is not None and not (isinstance(target, tuple) and len(target) == 2):
            raise InvalidValueError(f'{self.name}: target must be (obj, "attr") or (mapping, key)')

    @property
    def name(self) -> str:
        return f'{self.module}_{self.variable}'


def typed_value(text: str) -> bool | int | float | str:
    """A carmen.ini value as the daemon serves it: an int, a float, on/off (any case) as a bool,
    else the text.

    :param text: the value's text (surrounding blanks are ignored); an integer beyond 64 bits is
        taken as a float, a number beyond a float's range stays text.
    """
    text = text.strip()
    if _INT.fullmatch(text) and abs(int(text)) < 2**63:
        return int(text)
    if _FLOAT.fullmatch(text) and math.isfinite(float(text)):
        return float(text)
    return _ONOFF.get(text.lower(), text)


def text_of(value: Any) -> str:
    """A value as CARMEN's text: on/off for a bool.

    :param value: any value; ``str()`` of anything but a bool.
    """
    if isinstance(value, bool):
        return 'on' if value else 'off'
    return str(value)


def convert(value: Any, kind: ParamType | str, name: str) -> Any:
    """``value`` (a served value, or text) as ``kind`` — the conversion on demand of section 6:
    an int is a fine double, anything is a string (its text).

    :param value: a served value (bool, int, float, str) or carmen.ini text.
    :param kind: the type asked for, a ParamType or its value (``'int'``).
    :param name: the parameter's name, for the error (``robot_max_t_vel``).
    :raises ParamTypeError: naming the parameter, its value and the type asked for.
    """
    kind = ParamType(kind)
    if kind is ParamType.STRING:
        return text_of(value)
    if isinstance(value, str):
        value = typed_value(value)
    if kind is ParamType.ONOFF and isinstance(value, bool):
        return value
    if not isinstance(value, bool):
        if kind is ParamType.INT and isinstance(value, int):
            return value
        if kind is ParamType.DOUBLE and isinstance(value, (int, float)):
            return float(value)
    article = 'an' if kind is ParamType.INT else 'a'
    raise ParamTypeError(f'{name} is {text_of(value)!r}, not {article} {kind.value}')


def param_table(program: str, params: Sequence[Param]) -> str:
    """The ``-h`` listing of 6.2: each parameter, its type and whether it is subscribed.

    :param program: the program's name, in the first line.
    :param params: the parameter factory's list.
    """
    width = max([len(p.name) for p in params] + [4])
    lines = [f'{program}: parameters (from the parameter server; -VARIABLE VALUE overrides one)',
             f'  {"name":<{width}}  type    subscribed']
    lines += [f'  {p.name:<{width}}  {ParamType(p.type).value:<6}  {"yes" if p.subscribe else "no"}'
              for p in params]
    return '\n'.join(lines)


def assign(target: Target | None, value: Any) -> None:
    """Put ``value`` where ``target`` says.

    :param target: ``(obj, 'attr')`` (set as an attribute) or ``(mapping, key)`` (a mutable
        mapping's item); None: nothing is done.
    :param value: the value.
    """
    if target is None:
        return
    obj, key = target
    if isinstance(obj, MutableMapping):
        obj[key] = value
    else:
        setattr(obj, key, value)


def as_served(text: str, served: Any) -> Any:
    """``text`` as the served value's type, where it reads as one; else as the daemon types
    carmen.ini text (the daemon then refuses a mismatch with its reason).

    :param text: the new value's text (``true``/``false`` are taken for a bool too).
    :param served: the value the daemon serves now, or None when it has none.
    """
    if isinstance(served, str):
        return text
    kind = {bool: ParamType.ONOFF, int: ParamType.INT, float: ParamType.DOUBLE}.get(type(served))
    if kind is ParamType.ONOFF and text.lower() in ('true', 'false'):
        return text.lower() == 'true'
    if kind is not None:
        try:
            return convert(text, kind, '')
        except ParamTypeError:
            pass
    return typed_value(text)
