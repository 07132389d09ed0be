"""Keys from a terminal, one at a time: the input of Pluto's keyboard programs (Pluto 5: "each
module has a simple user interface that allows control from the keyboard ... xxx_i").

The terminal is put in cbreak mode (keys arrive as typed, not echoed; Ctrl-C still interrupts) and
restored on exit, also after an exception.  Arrow keys arrive as escape sequences and are named
``up``, ``down``, ``left``, ``right``; the space bar is ``space``; other keys are their character.
"""

from __future__ import annotations

import contextlib
import os
import select
import termios
import tty
from collections.abc import Iterator
from typing import IO

__all__ = ['Keyboard', 'decode']

_ARROWS = {'A': 'up', 'B': 'down', 'C': 'right', 'D': 'left'}


def decode(text: str) -> list[str]:
    """The keys in ``text`` (what one read returned), in order."""
    keys: list[str] = []
    i = 0
    while i < len(text):
        if text[i] == '\x1b' and i + 2 < len(text) and text[i + 1] in '[O' and text[i + 2] in _ARROWS:
            keys.append(_ARROWS[text[i + 2]])
            i += 3
            continue
        keys.append('space' if text[i] == ' ' else text[i])
        i += 1
    return keys


class Keyboard:
    """``with Keyboard(sys.stdin) as kb: kb.keys(0.05)``."""

    def __init__(self, stream: IO[str]) -> None:
        self.fd = stream.fileno()
        if not os.isatty(self.fd):
            raise OSError('standard input is not a terminal: a keyboard program needs one')
        self._saved: list | None = None
        self._pending = ''

    def __enter__(self) -> 'Keyboard':
        self._saved = termios.tcgetattr(self.fd)
        tty.setcbreak(self.fd)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._saved is not None:
            termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)
            self._saved = None

    @contextlib.contextmanager
    def cooked(self) -> Iterator[None]:
        """The terminal as it was (lines, echo) for the block: a program asking for numbers."""
        if self._saved is None:
            yield
            return
        termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)
        try:
            yield
        finally:
            tty.setcbreak(self.fd)

    def keys(self, timeout: float) -> list[str]:
        """The keys typed, waiting at most ``timeout`` s for the first one."""
        ready, _, _ = select.select([self.fd], [], [], timeout)
        if not ready:
            return []
        text = self._pending + os.read(self.fd, 256).decode(errors='replace')
        # An escape sequence split between two reads waits for its end.
        cut = text.rfind('\x1b')
        if cut >= 0 and len(text) - cut < 3:
            text, self._pending = text[:cut], text[cut:]
        else:
            self._pending = ''
        return decode(text)
