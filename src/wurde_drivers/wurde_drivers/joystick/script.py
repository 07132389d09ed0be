"""The ``joystick_emulator``'s command language: one command per line, from stdin or a file.

::

    axis translate -20000     # move an axis (a name from the joystick config, or its number)
    button stop 1             # press a button (0 releases it)
    press quit                # the same as "button quit 1"
    release quit              # the same as "button quit 0"
    wait 0.5                  # pause the script (s); the joystick keeps its state
    wait-reader               # pause until a program has the joystick open
    quit                      # end the emulator

Blank lines and ``#`` comments are ignored.  Pure Python: :func:`parse_command` turns a line into
a :class:`Command` or raises :class:`ScriptError` saying why.
"""

from __future__ import annotations

import dataclasses

from wurde_idl.errors import WurdeError

from .codec import AXIS_MAX
from .config import JoystickLayout

__all__ = ['Command', 'ScriptError', 'parse_command']


class ScriptError(WurdeError, ValueError):
    """A line that is not a command (the message says why)."""


@dataclasses.dataclass(frozen=True)
class Command:
    """``verb`` is ``axis``, ``button``, ``wait``, ``wait-reader`` or ``quit``; ``number`` the
    axis or button; ``value`` the axis value, 0/1 for a button, seconds for ``wait``."""

    verb: str
    number: int = 0
    value: float = 0


def _number(word: str, names: dict[str, int], kind: str) -> int:
    if word in names:
        return names[word]
    try:
        number = int(word)
    except ValueError:
        known = ', '.join(sorted(names)) or 'none (give a number)'
        raise ScriptError(f'no {kind} named "{word}" (names: {known})') from None
    if number < 0:
        raise ScriptError(f'{kind} number {number} is negative')
    return number


def _integer(word: str, what: str) -> int:
    try:
        return int(word)
    except ValueError:
        raise ScriptError(f'{what} "{word}" is not an integer') from None


def parse_command(line: str, layout: JoystickLayout) -> Command | None:
    """The command on ``line`` (None for a blank or comment line).

    :raises ScriptError: an unknown verb, a wrong number of words, a bad name or value.
    """
    words = line.split('#', 1)[0].split()
    if not words:
        return None
    verb, args = words[0].lower(), words[1:]
    expected = {'axis': 2, 'button': 2, 'press': 1, 'release': 1, 'wait': 1, 'wait-reader': 0,
                'quit': 0}
    if verb not in expected:
        raise ScriptError(f'unknown command "{words[0]}" (commands: {", ".join(expected)})')
    if len(args) != expected[verb]:
        raise ScriptError(f'"{verb}" takes {expected[verb]} argument(s), not {len(args)}')
    if verb == 'axis':
        value = _integer(args[1], 'axis value')
        if not -AXIS_MAX <= value <= AXIS_MAX:
            raise ScriptError(f'axis value {value} is not within -{AXIS_MAX} .. {AXIS_MAX}')
        return Command('axis', _number(args[0], layout.axes, 'axis'), value)
    if verb in ('button', 'press', 'release'):
        number = _number(args[0], layout.buttons, 'button')
        if verb != 'button':
            return Command('button', number, 1 if verb == 'press' else 0)
        value = _integer(args[1], 'button value')
        if value not in (0, 1):
            raise ScriptError(f'button value {value} is not 0 (released) or 1 (pressed)')
        return Command('button', number, value)
    if verb == 'wait':
        try:
            seconds = float(args[0])
        except ValueError:
            raise ScriptError(f'wait "{args[0]}" is not a number of seconds') from None
        if not 0.0 <= seconds <= 3600.0:
            raise ScriptError(f'wait {seconds} is not within 0 .. 3600 s')
        return Command('wait', value=seconds)
    return Command(verb)
