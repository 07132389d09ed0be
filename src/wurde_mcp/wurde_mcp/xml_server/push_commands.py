"""The ``push`` and ``varpush`` commands: add, list and remove a client's pushes (:mod:`.push`).

AU Robot Servers, "Server push": ``<push t=1.5 cmd="var odopose.pose"/>`` runs the command every
1.5 s, ``<varpush struct=odoPose i=3 cmd="var odopose.pose"/>`` on every third update of structure
``odoPose``.  The reply's tag is the command's own; a refused push is a ``warning`` reply.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from .command import Command, CommandError, parse_command, reply
from .push import EventPush, Push, TimePush
from .session import Session
from .variables import VariablePool

__all__ = ['PushCommands', 'push_help', 'varpush_help']


def push_help(min_period: float, max_pushes: int) -> str:
    """The ``push help`` text."""
    return ('-------------------- Available PUSH options:\n'
            f't=T cmd="command"       Run command every T seconds (T >= {min_period:g})\n'
            '                        for this client\n'
            'list                    List the pushes of this client (time and update pushes)\n'
            'flush                   Remove all pushes of this client\n'
            'help                    This help message\n'
            f'Pushes end with the client; at most {max_pushes} per client\n'
            'See also VARPUSH (update event handling)')


def varpush_help(max_pushes: int) -> str:
    """The ``varpush help`` text."""
    return ('-------------------- Available VARPUSH options:\n'
            'struct=S [i=N] cmd="command"  Run command on every N-th update of structure S\n'
            '                        (N default 1), e.g. struct=odoPose cmd="var odoPose.pose"\n'
            'list                    List the pushes of this client (time and update pushes)\n'
            'flush                   Remove all pushes of this client\n'
            'help                    This help message\n'
            f'Pushes end with the client; at most {max_pushes} per client\n'
            'See also PUSH (timed push)')


class PushCommands:
    """The ``push`` and ``varpush`` command handler."""

    #: Commands a push may not run.
    NOT_PUSHABLE = frozenset({'push', 'varpush'})

    def __init__(self, pool: VariablePool, *, min_period: float, max_pushes: int,
                 is_command: Callable[[str], bool], clock: Callable[[], float]) -> None:
        self._pool = pool
        self._min_period = min_period
        self._max_pushes = max_pushes
        self._is_command = is_command
        self._clock = clock

    def __call__(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        if command.has('list'):
            lines = [reply(tag, push.describe()) for push in client.pushes]
            return lines + [reply(tag, [('info', 'done')])]
        if command.has('flush'):
            count = len(client.pushes)
            client.pushes.clear()
            return [reply(tag, [('info', f'flushed {count} push{"" if count == 1 else "es"}'),
                                ('count', str(count))])]
        try:
            push = self._new_push(client, command)
        except ValueError as exc:
            return [reply(tag, [('warning', str(exc))])]
        client.pushes.append(push)
        return [reply(tag, [('info', f'added push {push.number}'), *push.describe()[:-1]])]

    def event_push(self, client: Session, keyword: str, cmd: str | None, struct: str,
                   every: str | None) -> EventPush:
        """An update push of ``client`` running ``cmd`` on every ``every``-th update of ``struct``
        (a structure or variable), as ``varpush`` and the ``*Push`` commands make; not yet added.

        :raises ValueError: why it cannot be (the client is told).
        """
        pushed = self._pushed(client, keyword, cmd, 'struct=name')
        var = self._pool.find(struct)
        if struct.strip('.') and self._pool.is_struct(struct):
            name = self._pool.struct_name(struct)
        elif var is not None:
            name = var.name
        else:
            raise ValueError(f'struct "{struct}" not found - try: var list')
        count = _number(every or '1', 'i')
        if not (math.isfinite(count) and count == int(count) and count >= 1):
            raise ValueError(f'i={every} is not a count of 1 or more')
        assert cmd is not None
        return EventPush(client.new_push_number(), cmd, pushed, name, int(count),
                         self._pool.updates(name))

    def _pushed(self, client: Session, keyword: str, cmd: str | None, needs: str) -> Command:
        """``cmd`` parsed, if a push of ``client`` may run it. :raises ValueError: why not."""
        if not cmd:
            raise ValueError(f'{keyword} needs {needs} and cmd="command" - try: {keyword} help')
        try:
            pushed = parse_command(cmd)
        except CommandError as exc:
            raise ValueError(f'bad cmd "{cmd}": {exc}') from None
        name = pushed.tag.lower()
        if pushed.kind != 'command':
            raise ValueError(f'bad cmd "{cmd}": not a command')
        if name in self.NOT_PUSHABLE or name.endswith('push') or name.endswith('onconnect'):
            raise ValueError(f'a push cannot run {pushed.tag}')
        if not self._is_command(name):
            raise ValueError(f'cmd {pushed.tag}: Unsupported function keyword')
        if len(client.pushes) >= self._max_pushes:
            raise ValueError(f'too many pushes: {len(client.pushes)} (max {self._max_pushes}) '
                             f'- try: {keyword} flush')
        return pushed

    def _new_push(self, client: Session, command: Command) -> Push:
        """The push ``command`` asks for. :raises ValueError: why it cannot be."""
        keyword = command.tag.lower()
        cmd = command.get('cmd')
        if keyword != 'push':
            return self.event_push(client, keyword, cmd, command.get('struct') or '',
                                   command.get('i'))
        pushed = self._pushed(client, keyword, cmd, 't=seconds')
        assert cmd is not None
        period = _number(command.get('t'), 't')
        if not period >= self._min_period or math.isinf(period):
            raise ValueError(f't={command.get("t")} is not a period of at least '
                             f'{self._min_period:g} s')
        return TimePush(client.new_push_number(), cmd, pushed, period, self._clock())


def _number(text: str | None, key: str) -> float:
    try:
        return float(text or '')
    except ValueError:
        raise ValueError(f'{key}="{text or ""}" is not a number') from None
