"""A client of an xmlServer (or of any Mobotware server): send a command, get its reply lines.

    with XmlClient(port=24919) as robot:
        print(robot.get('odoPose.pose')['value'])
        robot.request('push t=0.5 cmd="var odoPose.pose"')
        for line in robot.lines(timeout=5.0):
            print(line['x'], line['y'], line['th'])

Every reply line comes back as a dict of its attributes, with the tag name under the key ``''``
(``{'': 'var', 'name': 'odoPose.pose', 'typ': 'pose', ...}``; a bare keyword maps to ``''``).  A
closing tag comes back as ``{'': '/help'}``; a line of help text as ``{'': '', 'text': '...'}``.

Where a reply ends (:meth:`XmlClient.request`): a help block (``<help ...>`` to ``</help>``) and
any other block (``<odoPose name="poses">`` to ``</odoPose>``) are always read to their end; a
reply ends at a line with ``info="done"``, at the server's closing root
tag or when the server closes.  Otherwise one line is the whole reply unless the command is one
that the server ends with ``info="done"``: ``help`` or ``<cmd help/>``, ``push list``, and a
``var`` with other than exactly one variable or with ``list``, ``desc`` or ``allcopy``.  Pass
``until_done=True`` (or False) to say it for a command the rule does not know.
"""

from __future__ import annotations

import socket
import time
from collections.abc import Iterator, Sequence

from .command import Command, CommandError, opening, parse_command, reply
from .variables import VarError

__all__ = ['XmlClient']

_VAR_FLAGS = frozenset({'list', 'desc', 'allcopy', 'copy'})
_VAR_OPTIONS = frozenset({'type', 'call', 'returntype', 'dest'})


class XmlClient:
    """One connection to an xmlServer.

    :raises OSError: the server cannot be reached (``ConnectionRefusedError`` also when it has
        max clients already: its warning is the message).
    :raises TimeoutError: no greeting within ``timeout`` s.
    """

    def __init__(self, host: str = '127.0.0.1', port: int = 24919, timeout: float = 5.0, *,
                 name: str = 'xmlClient', version: str = '1.0') -> None:
        """Connect and exchange the greetings.

        :param host: the server's address.
        :param port: the server's TCP port (an xmlServer's default is 24919).
        :param timeout: how long the connection, the greeting and each request wait (s).
        :param name: the tag of this client's opening root line (replies to a warning carry it).
        :param version: the version its opening line gives.
        """
        #: How long a request waits for its reply (s).
        self.timeout = timeout
        #: The server's root tag and the name and version its greeting gave.
        self.root = ''
        self.server_name = ''
        self.server_version = ''
        self._buffer = bytearray()
        self._in_help = False
        self._block = ''                # the tag of an open reply block (<odoPose name="poses">)
        self._closed = False
        self._sock = socket.create_connection((host, port), timeout)
        try:
            self._greeting(time.monotonic() + timeout)
            self._send('<?xml version="1.0" encoding="UTF-8"?>\n' +
                       opening(name, [('name', name), ('version', version)]))
        except BaseException:
            self._sock.close()
            raise

    def __enter__(self) -> XmlClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def request(self, line: str, *, until_done: bool | None = None) -> list[dict[str, str]]:
        """Send one command line and return its reply lines (see the module's rule on where a
        reply ends).  A warning is a reply like any other.

        :param line: one command, tagged (``<var odoPose.pose=""/>``) or lazy (``var odoPose.pose``).
        :param until_done: whether the reply ends with an ``info="done"`` line (None: the module's
            rule decides).
        :returns: the reply lines as dicts, the tag under ``''``.
        :raises TimeoutError: the reply did not end within :attr:`timeout`.
        :raises OSError: the connection failed.
        """
        try:
            command: Command | None = parse_command(line)
        except CommandError:
            command = None                     # the server answers one error line
        many = _ends_with_done(command) if until_done is None else until_done
        self._send(line.rstrip('\r\n') + '\n')
        deadline = time.monotonic() + self.timeout
        replies: list[dict[str, str]] = []
        while True:
            item = self._next(deadline)
            if item is None:
                return replies
            replies.append(item)
            if self._in_help or item[''] == '/help':
                many = True
            elif self._block:
                continue
            elif item.get('info') == 'done' or item[''] == f'/{self.root}' or not many:
                return replies

    def get(self, name: str) -> dict[str, str]:
        """The reply line of variable ``name`` (``value``, ``typ``, ``size``; ``x y th`` of a pose).

        :param name: a variable's full name, e.g. ``odoPose.pose`` (not case sensitive).
        :raises VarError: the server's warning (no such variable, or a structure).
        :raises ValueError: ``name`` is not a variable name.
        """
        return self._one(self.request(reply('var', [(name, '')])), name)

    def set(self, name: str, value: str | float | Sequence[float]) -> dict[str, str]:
        """Set variable ``name`` (numbers are written for you); the reply line (with ``oldValue``).

        :param name: a variable's full name (a new one is made, as the server's ``var X=...``).
        :param value: the text as sent, a number, or a sequence of numbers (written space-separated).
        :raises VarError: the server's warning (read-only, a bad value, refused).
        :raises ValueError: an empty value (it would read the variable, not set it).
        """
        if isinstance(value, (int, float)):
            text = f'{value:.15g}'
        elif isinstance(value, str):
            text = value
        else:
            text = ' '.join(f'{v:.15g}' for v in value)
        if not text:
            raise ValueError(f'set({name!r}): an empty value cannot be set')
        return self._one(self.request(reply('var', [(name, text)])), name)

    def lines(self, timeout: float | None = None) -> Iterator[dict[str, str]]:
        """The lines the server sends (pushes), until the time is up or the server closes.

        :param timeout: how long to read from now (s); None: until the server closes the
            connection.
        """
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            try:
                item = self._next(deadline)
            except TimeoutError:
                return
            if item is None:
                return
            yield item

    def help(self, command: str = '') -> str:
        """The text of the server's help (``help``) or of a command's (``help('var')``).

        :param command: a command's keyword ('' for the server's help).
        """
        replies = self.request(f'{command} help' if command else 'help', until_done=True)
        return '\n'.join(item['text'] for item in replies if 'text' in item and item[''] == '')

    def close(self) -> None:
        """Send ``q`` and close (idempotent)."""
        if self._closed:
            return
        self._closed = True
        try:
            self._sock.sendall(b'q\n')
        except OSError:
            pass
        self._sock.close()

    # ---- lines --------------------------------------------------------------------------------

    def _greeting(self, deadline: float) -> None:
        for _ in range(2):
            item = self._next(deadline)
            if item is None:
                raise ConnectionError('the server closed the connection before its greeting')
            if 'warning' in item or 'error' in item:
                raise ConnectionRefusedError(item.get('warning') or item.get('error'))
            if item[''] != 'xml':
                self.root = item['']
                self.server_name = item.get('name', '')
                self.server_version = item.get('version', '')
                return
        raise ConnectionError('no opening root tag in the server greeting')

    def _send(self, text: str) -> None:
        if self._closed:
            raise OSError('XmlClient is closed')
        self._sock.sendall(text.encode())

    def _next(self, deadline: float | None) -> dict[str, str] | None:
        """The next line as a dict, None when the server closed the connection.

        :raises TimeoutError: nothing came by ``deadline`` (monotonic s; None: no deadline).
        """
        line = self._readline(deadline)
        if line is None:
            return None
        if self._in_help:
            if line.strip() == '</help>':
                self._in_help = False
                return {'': '/help'}
            return {'': '', 'text': line}
        try:
            command = parse_command(line)
        except CommandError:
            return {'': '', 'text': line}
        if command.is_closing:
            if command.tag == self._block:
                self._block = ''
            return {'': f'/{command.tag}'}
        if command.kind == 'opening' and command.tag == 'help':
            self._in_help = True
        elif command.kind == 'opening' and self.root and command.tag != self.root:
            self._block = command.tag
        item = {'': command.tag}
        item.update((key, '' if value is None else value) for key, value in command.args)
        return item

    def _readline(self, deadline: float | None) -> str | None:
        while True:
            newline = self._buffer.find(b'\n')
            if newline >= 0:
                raw = bytes(self._buffer[:newline])
                del self._buffer[:newline + 1]
                return raw.decode('utf-8', errors='replace').rstrip('\r')
            if deadline is None:
                self._sock.settimeout(None)
            else:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise TimeoutError('no reply line in time')
                self._sock.settimeout(left)
            try:
                data = self._sock.recv(65536)
            except socket.timeout:
                raise TimeoutError('no reply line in time') from None
            if not data:
                return None
            self._buffer += data

    @staticmethod
    def _one(replies: list[dict[str, str]], name: str) -> dict[str, str]:
        if not replies:
            raise ConnectionError('the server closed the connection')
        first = replies[0]
        if 'warning' in first or 'error' in first:
            raise VarError(first.get('warning') or first.get('error'))
        if first[''] == 'help':
            raise VarError(f'{name} is a structure - try: request("var {name}")')
        return first


def _ends_with_done(command: Command | None) -> bool:
    """Whether the server ends its reply to ``command`` with an ``info="done"`` line."""
    if command is None or command.kind != 'command':
        return False
    name = command.tag.lower()
    if name == 'help' or command.has('help'):
        return True
    if name in ('push', 'varpush'):
        return command.has('list')
    if name == 'var':
        if command.has('log') or command.has('islogging'):
            return False                # one line per name
        requests = [key for key, value in command.args if key.lower() not in _VAR_OPTIONS and
                    (value or key.lower() not in _VAR_FLAGS)]
        if command.has('call') and not requests:
            return False                # one <var method=...> block
        flagged = any(not value and key.lower() in _VAR_FLAGS for key, value in command.args)
        return flagged or len(requests) != 1 or requests[0].lower().endswith('.allcopy') or \
            command.has('call')
    return False
