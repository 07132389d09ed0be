"""One connected client of the xmlServer: its socket, bounded input and output buffers and pushes.

The server (:mod:`.server`) owns the sessions; a command handler gets the client's :class:`Session`
and may read :attr:`Session.address`, :attr:`Session.number` and :attr:`Session.pushes`, note
what it told the client once in :attr:`Session.told`, and end the session with
:meth:`Session.end`.  Both buffers are bounded, so a client can make the server hold at most
``max_line + 1`` bytes of its input and ``send_buffer`` bytes of its output.
"""

from __future__ import annotations

import math
import socket
from typing import Any, Final

from .push import Push

__all__ = ['TOO_LONG', 'Session']


class _TooLong:
    def __repr__(self) -> str:
        return 'TOO_LONG'


#: What :meth:`Session.next_line` returns for a line longer than ``max_line`` (it is dropped).
TOO_LONG: Final = _TooLong()


class Session:
    """One client's connection, as the server drives it and as command handlers see it."""

    def __init__(self, sock: socket.socket, address: Any, number: int, now: float) -> None:
        #: The client's socket (non-blocking); only the server uses it.
        self.sock = sock
        #: The client's address, as ``accept()`` gave it (host, port).
        self.address = address
        #: The session's number: 1 for the server's first client, and so on.
        self.number = number
        #: This client's pushes (:mod:`.push`), in the order they were added.
        self.pushes: list[Push] = []
        #: When something was last received from this client or sent to it (monotonic s).
        self.last_activity = now
        #: What this client was warned about once per session (a handler's keys, e.g. ``pt``).
        self.told: set[str] = set()
        #: The client closed its side: no more input, but the lines already received are handled.
        self.eof = False
        #: The session is ending: its output is sent, then it is closed (by :attr:`end_deadline`).
        self.ending = False
        self.end_deadline = math.inf
        self.closed = False
        self._end_requested = False
        self._next_push = 1
        self._in = bytearray()
        self._pos = 0                   # start of what is not yet taken from _in
        self._discarding = False        # dropping the rest of a too long line
        self._out = bytearray()

    def __repr__(self) -> str:
        return f'<Session {self.number} {self.address}>'

    def end(self) -> None:
        """End this session once the current command's reply is sent (``q``, ``</marg>``)."""
        self._end_requested = True

    @property
    def end_requested(self) -> bool:
        return self._end_requested

    def new_push_number(self) -> int:
        """The next number of a push of this client (1, 2, ...; never reused in a session)."""
        number = self._next_push
        self._next_push += 1
        return number

    # ---- input --------------------------------------------------------------------------------

    @property
    def buffered_input(self) -> int:
        """Bytes received and not yet handled."""
        return len(self._in) - self._pos

    def has_line(self) -> bool:
        """Whether a complete line waits in the input buffer."""
        return self._in.find(b'\n', self._pos) >= 0

    def receive(self, max_line: int) -> bool:
        """Read what the socket has, at most up to ``max_line + 1`` bytes buffered; False at EOF.

        Call only when :meth:`has_line` is False, so that the buffer holds at most one partial line.

        :raises OSError: the connection failed.
        """
        if self._pos:
            del self._in[:self._pos]
            self._pos = 0
        room = max_line + 1 - len(self._in)
        if room <= 0:                   # a too long partial line: next_line() drops it first
            return True
        try:
            data = self.sock.recv(room)
        except (BlockingIOError, InterruptedError):
            return True
        if not data:
            return False
        self._in += data
        return True

    def next_line(self, max_line: int) -> str | _TooLong | None:
        """The next complete line (decoded, invalid UTF-8 replaced), :data:`TOO_LONG` for a line
        of more than ``max_line`` bytes (dropped up to its newline), or None: no line complete."""
        while True:
            newline = self._in.find(b'\n', self._pos)
            if newline < 0:
                if self._discarding or len(self._in) - self._pos > max_line:
                    del self._in[:]
                    self._pos = 0
                    if not self._discarding:
                        self._discarding = True
                        return TOO_LONG
                return None
            raw = bytes(self._in[self._pos:newline])
            self._pos = newline + 1
            if self._discarding:        # the tail of a line already reported as too long
                self._discarding = False
                continue
            if len(raw) > max_line:
                return TOO_LONG
            return raw.decode('utf-8', errors='replace')

    # ---- output -------------------------------------------------------------------------------

    @property
    def pending_output(self) -> int:
        """Bytes queued and not yet taken by the socket."""
        return len(self._out)

    def queue(self, data: bytes, limit: int) -> bool:
        """Queue ``data``; False (nothing queued) when the output would pass ``limit`` bytes even
        after sending what the socket takes now: the client does not read fast enough.

        :raises OSError: the connection failed.
        """
        if len(self._out) + len(data) > limit:
            self.flush()
            if len(self._out) + len(data) > limit:
                return False
        self._out += data
        return True

    def flush(self, now: float | None = None) -> int:
        """Send what the socket takes without blocking; the number of bytes sent.

        :raises OSError: the connection failed.
        """
        if not self._out:
            return 0
        try:
            sent = self.sock.send(self._out)
        except (BlockingIOError, InterruptedError):
            return 0
        del self._out[:sent]
        if sent and now is not None:
            self.last_activity = now
        return sent
