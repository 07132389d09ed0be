"""Mobotware's ``if`` module: this server as a client of another server (AU Robot Servers, "Get
value to another server")::

    module load=if alias=cam
    cam connect=localhost:24920
    cam varpush struct=gmk cmd="var gmk copy"

``module load=if alias=cam`` (:mod:`.core_commands`) makes an :class:`InterfaceModule` with the
commands ``cam`` and ``camOnConnect``.  ``cam connect=host:port`` connects (retrying every
:data:`RETRY_S` until ``cam hup``); any other option of ``cam`` starts a command sent to the other
server as it is written (``cam varpush ...`` sends ``varpush ...``; ``cam cmd="..."`` too), answered
``info="send: ...\\n"``.  The other server's ``<var name= typ= value=/>`` lines are kept here: in the
structure ``var`` (``var.gmk.count``), in the root with ``dest=.``, under ``dest=struct.`` or as the
variable ``dest=name``; ``desc=`` becomes the description, else "added".  ``camOnConnect cmd="..."``
adds a command sent on every (re)connection.

Connecting never blocks the server's turn: the socket is non-blocking and watched by the server's
selector; only numeric addresses and ``localhost`` are taken (no name lookup in the loop), input
lines and output are bounded as a client's are, and a failure only ends this connection.
"""

from __future__ import annotations

import errno
import ipaddress
import logging
import selectors
import socket
import time

from .command import Command, CommandError, escape, help_block, opening, parse_command, reply
from .host import ServerHost
from .session import Session
from .user_vars import COPY_STRUCT
from .variables import VarError

__all__ = ['IF_NAME', 'InterfaceModule', 'RETRY_S']

#: How often a lost or refused connection is tried again (s).
RETRY_S = 1.0
#: Most commands sent on connect.
MAX_ON_CONNECT = 32
#: The module's name in ``module list``.
IF_NAME = 'if (server interface client)'
#: AURS options of the if module this server does not have.
_UNSUPPORTED = frozenset({'trap', 'stx', 'replay', 'warning', 'info', 'binname', 'allisbin',
                          'verbose'})

_log = logging.getLogger(__name__)


def if_help(alias: str) -> str:
    """``cam help``."""
    return (f'----------- available {alias.upper()} options\n'
            'connect[="host:port"]       Connect to server (host an address or localhost)\n'
            'cmd="cmd for server"        Send command to server\n'
            f'  e.g.: <{alias} cmd="var list"/> or just: {alias} var list\n'
            'hup                         Disconnect (hangup)\n'
            'status                      Status for interface\n'
            'help                        This help tekst\n'
            '                            Received var tags go to the structure var,\n'
            '                            or where their dest= says (. the root)\n'
            '------\n'
            f"See also '{alias}OnConnect'")


def on_connect_help(alias: str) -> str:
    """``camOnConnect help``."""
    return ('----------------Available OnConnect options:\n'
            'flush           Remove all commands\n'
            'cmd="cmd"       Do execute \'cmd\' command on connect\n'
            'list            List all defined commands (as help text)\n'
            '---')


class InterfaceModule:
    """One ``if`` module: its commands and its connection to another server."""

    def __init__(self, server: ServerHost, alias: str) -> None:
        self.server = server
        self.alias = alias
        self.host = ''
        self.port = 0
        self.received = 0           # var lines kept
        self.refused = 0            # var lines not kept
        self.last_refusal = ''
        self._sock: socket.socket | None = None
        self._connected = False
        self._wanted = False
        self._retry_at = 0.0
        self._in = bytearray()
        self._out = bytearray()
        self._discarding = False
        self._on_connect: list[str] = []

    @property
    def connected(self) -> bool:
        return self._connected

    def install(self) -> None:
        """Add ``alias`` and ``aliasOnConnect`` to the server. :raises ValueError: a name taken."""
        self.server.add_command(self.alias, self.command, 'Interface to another server',
                                help_text=if_help(self.alias), group=self.alias)
        try:
            self.server.add_command(f'{self.alias}OnConnect', self.on_connect,
                                    'Commands sent on connect',
                                    help_text=on_connect_help(self.alias), group=self.alias)
        except ValueError:
            self.server.remove_command(self.alias)
            raise
        self.server.add_poller(self.poll)

    def uninstall(self) -> None:
        """Hang up and remove the commands."""
        self.hang_up()
        self.server.remove_poller(self.poll)
        for name in (self.alias, f'{self.alias}OnConnect'):
            self.server.remove_command(name)

    # ---- commands -----------------------------------------------------------------------------

    def command(self, client: Session, command: Command) -> list[str]:
        tag, lines = command.tag, []
        for index, (key, value) in enumerate(command.args):
            lower = key.lower()
            if lower == 'connect':
                lines.append(self._connect_command(tag, value))
            elif lower == 'hup':
                self.hang_up()
                lines.append(reply(tag, [('info', 'HUP (hangup) requested')]))
            elif lower == 'status':
                lines += help_block(f'{self.alias.upper()} status', self._status(), tag)
            elif lower == 'cmd':
                lines.append(self._send_command(tag, value or ''))
            elif lower in _UNSUPPORTED:
                lines.append(reply(tag, [('warning', f'{key} is not supported by this '
                                                     'server\'s if module')]))
            else:                           # the rest of the line is a command for the server
                words = [k if v is None else f'{k}="{escape(v)}"' for k, v in command.args[index:]]
                lines.append(self._send_command(tag, ' '.join(words)))
                break
        return lines or [reply(tag, [('warning', 'Unknown subject')])]

    def on_connect(self, client: Session, command: Command) -> list[str]:
        tag = command.tag
        if command.has('list'):
            return help_block('OnConnect command list', '\n'.join(self._on_connect) or
                              'no commands', tag)
        if command.has('flush'):
            self._on_connect.clear()
        elif command.get('cmd'):
            if len(self._on_connect) >= MAX_ON_CONNECT:
                return [reply(tag, [('warning', 'push command failed: too many '
                                                f'(max {MAX_ON_CONNECT})')])]
            self._on_connect.append(command.get('cmd') or '')
        else:
            return [reply(tag, [('warning', 'push command failed: no cmd="..." - try: '
                                            f'{tag} help')])]
        return [reply(tag, [('info', f'push command succeded - now {len(self._on_connect)} '
                                     'pushCmds and 0 pushCalls')])]

    def _connect_command(self, tag: str, value: str | None) -> str:
        if value:
            host, colon, port = value.rpartition(':')
            try:
                number = int(port)
                address = '127.0.0.1' if host.lower() == 'localhost' else \
                    str(ipaddress.ip_address(host.strip('[]')))
            except ValueError:
                number, address = 0, ''
            if not colon or not address or not 0 < number < 65536:
                return reply(tag, [('warning', f'connect="{value}" is not host:port (host an '
                                               'address or localhost)')])
            self.host, self.port = address, number
        elif not self.port:
            return reply(tag, [('warning', 'connect needs ="host:port" the first time')])
        self.hang_up()
        self._wanted = True
        self._open()
        return reply(tag, [('info', f'connection requested to {self.host}:{self.port}')])

    def _send_command(self, tag: str, text: str) -> str:
        text = text.strip()
        if not text:
            return reply(tag, [('warning', 'no command to send')])
        if not self._connected:
            return reply(tag, [('warning', f'No connection to server - not send: {text}\\n')])
        if not self._queue(text + '\n'):
            return reply(tag, [('warning', f'the server does not read: not send: {text}\\n')])
        return reply(tag, [('info', f'send: {text}\\n')])

    def _status(self) -> str:
        return (f'This interface is connected ({str(self._connected).lower()}) to '
                f'{self.host or "-"} {self.port}\n'
                f'{self.received} var lines kept, {self.refused} refused'
                + (f' (last: {self.last_refusal})' if self.last_refusal else '') + '\n'
                f'{len(self._on_connect)} commands on connect')

    # ---- the connection -----------------------------------------------------------------------

    def hang_up(self) -> None:
        """Close the connection and stop retrying (idempotent)."""
        self._wanted = False
        self._close()

    def poll(self, now: float) -> None:
        """Retry a wanted connection when due (the server calls this every turn)."""
        if self._wanted and self._sock is None and now >= self._retry_at:
            self._open()

    def on_event(self, mask: int) -> None:
        """The socket is readable or writable (the server's selector says)."""
        if self._sock is None:
            return
        try:
            if not self._connected and mask & selectors.EVENT_WRITE:
                error = self._sock.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR)
                if error:
                    raise OSError(error, errno.errorcode.get(error, str(error)))
                self._established()
            if self._connected and mask & selectors.EVENT_READ:
                self._receive()
            if self._sock is not None and self._out:
                self._flush()
        except OSError as exc:
            _log.info('%s: connection to %s:%d: %s', self.alias, self.host, self.port, exc)
            self._close()

    def _open(self) -> None:
        self._retry_at = time.monotonic() + RETRY_S
        sock = socket.socket(socket.AF_INET6 if ':' in self.host else socket.AF_INET,
                             socket.SOCK_STREAM)
        sock.setblocking(False)
        code = sock.connect_ex((self.host, self.port))
        if code not in (0, errno.EINPROGRESS, errno.EWOULDBLOCK):
            _log.info('%s: connect to %s:%d: %s', self.alias, self.host, self.port,
                      errno.errorcode.get(code, code))
            sock.close()
            return
        self._sock = sock
        self.server.watch(sock, self, selectors.EVENT_WRITE)

    def _established(self) -> None:
        assert self._sock is not None
        self._connected = True
        s = self.server.settings
        hello = ('<?xml version="1.0" encoding="UTF-8"?>\n' +
                 opening(s.name, [('name', s.name), ('version', s.version),
                                  ('host', socket.gethostname()), ('port', str(self.server.port))]))
        self._queue(hello + ''.join(cmd + '\n' for cmd in self._on_connect))

    def _queue(self, text: str) -> bool:
        data = text.encode('utf-8', errors='replace')
        if len(self._out) + len(data) > self.server.settings.send_buffer:
            return False
        self._out += data
        self._flush()
        return True

    def _flush(self) -> None:
        if self._sock is None:
            return
        try:
            sent = self._sock.send(self._out)
        except (BlockingIOError, InterruptedError):
            sent = 0
        del self._out[:sent]
        self.server.watch(self._sock, self, selectors.EVENT_READ |
                          (selectors.EVENT_WRITE if self._out else 0))

    def _receive(self) -> None:
        assert self._sock is not None
        try:
            data = self._sock.recv(65536)
        except (BlockingIOError, InterruptedError):
            return
        if not data:
            raise ConnectionResetError('closed by the server')
        self._in += data
        limit = self.server.settings.max_line
        while True:
            newline = self._in.find(b'\n')
            if newline < 0:
                if len(self._in) > limit:           # a too long line: dropped to its newline
                    self._in.clear()
                    self._discarding = True
                return
            line = bytes(self._in[:newline]).decode('utf-8', errors='replace')
            del self._in[:newline + 1]
            if self._discarding:
                self._discarding = False
            elif len(line) <= limit:
                self._line(line)

    def _line(self, line: str) -> None:
        try:
            command = parse_command(line)
        except CommandError:
            return                                  # help text and the like
        if command.kind != 'command' or command.tag.lower() != 'var':
            return
        name, typ, value = command.get('name'), command.get('typ'), command.get('value')
        if name is None or typ is None or value is None:
            return                                  # info="done", warnings
        dest = command.get('dest')
        if dest is None:
            target = f'{COPY_STRUCT}.{name}'
        elif dest.endswith('.'):
            target = dest.lstrip('.') + name
        else:
            target = dest
        try:
            _, var = self.server.user_vars.put(target, typ, value, command.get('desc') or 'added')
        except VarError as exc:
            self.refused += 1
            self.last_refusal = f'{target}: {exc}'
            return
        if command.get('desc'):
            var.description = command.get('desc') or ''
        self.received += 1

    def _close(self) -> None:
        if self._sock is not None:
            self.server.unwatch(self._sock)
            self._sock.close()
        self._sock = None
        self._connected = False
        self._in.clear()
        self._out.clear()
        self._discarding = False
        self._retry_at = time.monotonic() + RETRY_S
