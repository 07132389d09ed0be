"""When a push is due: a client's command run again on a timer (``push``) or on updates of a
structure (``varpush``), as in the seed's "Server push" (``<push t=1.5 cmd="var odopose.pose"/>``).

A push belongs to one client (:attr:`.Session.pushes`) and ends with it.  The server asks each push
every turn whether it is due (:meth:`Push.poll`) and runs its command as if the client had sent it.
A time push is due at ``start + k * t`` (k = 1, 2, ...): a late turn does not shift the later ones,
and periods missed altogether (a stalled loop) are skipped, not run in a burst.  The ``push`` and
``varpush`` commands that make them are in :mod:`.push_commands`.
"""

from __future__ import annotations

import math

from .command import Command
from .variables import VariablePool

__all__ = ['EventPush', 'Push', 'TimePush']


class Push:
    """What every push has: its number, its command and how often it ran."""

    def __init__(self, number: int, cmd: str, command: Command) -> None:
        self.number = number
        #: The command's text as the client gave it, and parsed.
        self.cmd = cmd
        self.command = command
        #: How often the command was run.
        self.count = 0

    def poll(self, now: float, pool: VariablePool) -> bool:
        """Whether the command is due now; a True answer counts the run."""
        raise NotImplementedError

    def describe(self) -> list[tuple[str, str | None]]:
        """The attributes of this push's line in ``push list``."""
        raise NotImplementedError


class TimePush(Push):
    """Runs its command every ``period`` seconds from ``start``."""

    def __init__(self, number: int, cmd: str, command: Command, period: float,
                 start: float) -> None:
        super().__init__(number, cmd, command)
        self.period = period
        self.start = start
        self._ticks = 1
        #: When the command is next due (monotonic s).
        self.next_due = start + period

    def poll(self, now: float, pool: VariablePool) -> bool:
        if now < self.next_due:
            return False
        self._ticks = max(self._ticks + 1, math.floor((now - self.start) / self.period) + 1)
        self.next_due = self.start + self._ticks * self.period
        self.count += 1
        return True

    def describe(self) -> list[tuple[str, str | None]]:
        return [('number', str(self.number)), ('t', f'{self.period:g}'), ('cmd', self.cmd),
                ('count', str(self.count))]


class EventPush(Push):
    """Runs its command on every ``every``-th update of structure (or variable) ``struct``."""

    def __init__(self, number: int, cmd: str, command: Command, struct: str, every: int,
                 updates: int) -> None:
        super().__init__(number, cmd, command)
        self.struct = struct
        self.every = every
        self._seen = updates

    def pending(self, pool: VariablePool) -> bool:
        """Whether the push is due: the structure was updated ``every`` times since it last ran."""
        updates = pool.updates(self.struct)
        return updates < self._seen or updates - self._seen >= self.every

    def poll(self, now: float, pool: VariablePool) -> bool:
        updates = pool.updates(self.struct)
        if updates < self._seen:                # the count went back: start again from it
            self._seen = updates
        if updates - self._seen < self.every:
            return False
        self._seen += (updates - self._seen) // self.every * self.every
        self.count += 1
        return True

    def describe(self) -> list[tuple[str, str | None]]:
        return [('number', str(self.number)), ('struct', self.struct), ('i', str(self.every)),
                ('cmd', self.cmd), ('count', str(self.count))]
