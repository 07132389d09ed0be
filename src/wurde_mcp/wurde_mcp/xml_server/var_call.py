"""``var call='me(par1,par2,..)' [returnType=T]``: a method call, as AURS's var pool answers it
(AU Robot Servers, "Online help", VAR options ``call=`` and ``returnType=``).

The call is parsed as AURS parses it (a name, ``(``, numbers or quoted strings separated by commas,
``)``) and answered with ``<var method="me" par="dd" found="true" value="5" structCnt="0">`` and the
closing ``</var>`` (the command's tag; a value between 10 and 2e9, a UTM coordinate or a time, with
four decimals, else ``%g``).  This server has no plug-ins that own methods, so the methods are the
calculator's: :data:`METHODS`; an unknown one answers ``found="false" value="0"``.  No method here
returns a structure, so ``structCnt`` is 0 and ``returnType`` only names one AURS knows.
"""

from __future__ import annotations

import math
import re
import time
from collections.abc import Callable

from .command import closing, opening, reply, text

__all__ = ['METHODS', 'RETURN_TYPES', 'call_reply', 'parse_call']

#: The methods: name -> (parameter order, d a double and s a string; the function).
METHODS: dict[str, tuple[str, Callable[..., float]]] = {
    'sin': ('d', math.sin), 'cos': ('d', math.cos), 'tan': ('d', math.tan),
    'asin': ('d', math.asin), 'acos': ('d', math.acos), 'atan': ('d', math.atan),
    'atan2': ('dd', math.atan2), 'hypot': ('dd', math.hypot), 'sqrt': ('d', math.sqrt),
    'exp': ('d', math.exp), 'log': ('d', math.log), 'abs': ('d', abs),
    'floor': ('d', math.floor), 'ceil': ('d', math.ceil), 'round': ('d', round),
    'pi': ('', lambda: math.pi), 'now': ('', time.time),
    'limitToPi': ('d', lambda a: math.remainder(a, 2 * math.pi)),
    'max': ('dd', max), 'min': ('dd', min),
}

#: The structure types AURS's ``returnType=`` knows.
RETURN_TYPES = frozenset({'lineseg', 'pose', 'posetime', 'posev', '3d', 'position', 'string',
                          'var'})

_NUMBER = re.compile(r'[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?')


class CallError(ValueError):
    """A call that cannot be parsed; ``str()`` is AURS's warning."""


def parse_call(call: str) -> tuple[str, str, list[float | str]]:
    """``(method, parameter order, parameters)`` of ``me(1, 'a')``.

    :raises CallError: no brackets, or a parameter that is not a number or a quoted string.
    """
    method, bracket, rest = call.partition('(')
    if not bracket:
        raise CallError('method parsing error - must have prackets')
    order = ''
    params: list[float | str] = []
    rest = rest.lstrip()
    while not rest.startswith(')'):
        if rest[:1] in ('"', "'"):
            end = rest.find(rest[0], 1)
            if end < 0:
                raise CallError('method parameter parsing error')
            params.append(rest[1:end])
            order, rest = order + 's', rest[end + 1:]
        else:
            found = _NUMBER.match(rest)
            if found is None:
                raise CallError('method parameter parsing error')
            params.append(float(found.group()))
            order, rest = order + 'd', rest[found.end():]
        rest = rest.lstrip()
        if rest.startswith(','):
            rest = rest[1:].lstrip()
        elif not rest.startswith(')'):
            raise CallError('method parameter parsing error')
    return method.strip(), order, params


def call_reply(tag: str, call: str, return_type: str = '') -> list[str]:
    """The reply lines to ``call=`` (and ``returnType=``)."""
    try:
        method, order, params = parse_call(call)
    except CallError as exc:
        return [reply(tag, [('warning', str(exc))])]
    known = METHODS.get(method)
    value, found = 0.0, known is not None and known[0] == order
    if found:
        try:
            value = float(known[1](*params))             # type: ignore[index]
        except (ValueError, OverflowError, ZeroDivisionError):
            value = math.nan
    shown = f'{value:.4f}' if 10.0 < value < 2e9 else f'{value:g}'
    lines = [opening(tag, [('method', method), ('par', order), ('found', str(found).lower()),
                           ('value', shown), ('structCnt', '0')])]
    if return_type and return_type.lower() not in RETURN_TYPES:
        lines.append(text(f'Specified struct type {return_type} is not supported - (OK if '
                          'resource owns returned structures)'))
    return lines + [closing(tag)]
