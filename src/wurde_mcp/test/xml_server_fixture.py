"""What the xmlServer tests share: a test pool, a server served from a thread, a raw line client.

Every read has a deadline (:data:`DEADLINE`): a missing reply fails the test instead of hanging it.
"""

from __future__ import annotations

import contextlib
import socket
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

from wurde_mcp.xml_server import ServerSettings, Variable, VariablePool, VarError, XmlServer

#: A fixture that starts servers: ``start(**settings)``.
Start = Callable[..., XmlServer]

#: Longest wait for one expected line or event (s): generous, for a loaded machine.
DEADLINE = 8.0

POSE = [1.531, -21.912, -2.026, 1286376207.8752]
POSE_LINE = ('<var name="odoPose.pose" typ="pose" size="4" value="1.531 -21.912 -2.026 '
             '1286376207.8752" x="1.531" y="-21.912" th="-2.026"/>')
RANGES_LINE = '<var name="laser.ranges" typ="d" size="3" value="1 2.5 3.25"/>'


def _refuse_negative(value: Any) -> None:
    if value and value[0] < 0:
        raise VarError('refused: a negative speed')


def make_pool() -> VariablePool:
    """odoPose.pose (pose), laser.ranges (d, read-only), camPool.device0.name (s, read-only),
    camPool.device0.intrinsic (m2, writable), drive.speed (d, writable, refuses negatives)."""
    pool = VariablePool()
    pool.add(Variable('odoPose.pose', 'pose', '(r) odometry pose x, y [m], th [rad] and time [s] '
                      'of the robot seen from where it started', list(POSE)))
    pool.describe('odoPose', 'odometry of the base')
    pool.add(Variable('laser.ranges', 'd', '(r) ranges [m]', [1.0, 2.5, 3.25]))
    pool.add(Variable('camPool.device0.name', 's', '(r) camera name', 'Logitech Pro 3000'))
    pool.add(Variable('camPool.device0.intrinsic', 'm2', '(r/w) intrinsic matrix',
                      [[709.0, 0.0, 320.0], [0.0, 709.0, 240.0], [0.0, 0.0, 1.0]],
                      write=lambda value: None))
    pool.add(Variable('drive.speed', 'd', '(r/w) speed [m/s]; negative refused', [0.0],
                      write=_refuse_negative))
    return pool


@contextlib.contextmanager
def running(pool: VariablePool | None = None, *, setup: Callable[[XmlServer], None] | None = None,
            **settings: Any) -> Iterator[XmlServer]:
    """An XmlServer on a free port of 127.0.0.1, served by ``serve(0.02)`` in a thread; on exit the
    thread is stopped and joined, the server closed, and serve() must not have raised."""
    server = XmlServer(pool if pool is not None else make_pool(),
                       ServerSettings(port=0, version='1.0', **settings))
    if setup is not None:
        setup(server)
    server.start()
    stop = threading.Event()
    errors: list[BaseException] = []

    def loop() -> None:
        try:
            while not stop.is_set():
                server.serve(0.02)
        except BaseException as exc:            # reported by the test, not lost in the thread
            errors.append(exc)

    thread = threading.Thread(target=loop, name='xml-server', daemon=True)
    thread.start()
    try:
        yield server
    finally:
        stop.set()
        thread.join(DEADLINE)
        server.close()
        assert not thread.is_alive(), 'serve() did not return'
        assert errors == [], f'serve() raised {errors!r}'


def wait_until(predicate: Callable[[], bool], what: str, timeout: float = DEADLINE) -> None:
    """Poll ``predicate`` until true; fail naming ``what`` after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, f'timed out waiting for {what}'
        time.sleep(0.01)


class Raw:
    """A client on a raw socket: sends bytes, reads lines, each read with a deadline."""

    def __init__(self, port: int, *, greet: bool = True, rcvbuf: int | None = None) -> None:
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if rcvbuf is not None:
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        self.sock.connect(('127.0.0.1', port))
        self._buffer = bytearray()
        self.greeting = [self.line(), self.line()] if greet else []

    def send(self, data: str | bytes) -> None:
        self.sock.sendall(data.encode() if isinstance(data, str) else data)

    def ask(self, line: str) -> str:
        """Send ``line`` and its newline, return the next line."""
        self.send(line + '\n')
        return self.line()

    def line(self, timeout: float = DEADLINE) -> str:
        """The next line without its newline; fails at EOF or after ``timeout`` s."""
        line = self._line(time.monotonic() + timeout)
        assert line is not None, 'the server closed the connection'
        return line

    def until(self, predicate: Callable[[str], bool], timeout: float = DEADLINE) -> list[str]:
        """Lines up to and including the first one for which ``predicate`` holds."""
        deadline = time.monotonic() + timeout
        lines: list[str] = []
        while not lines or not predicate(lines[-1]):
            line = self._line(deadline)
            assert line is not None, f'the server closed the connection after {lines!r}'
            lines.append(line)
        return lines

    def until_done(self) -> list[str]:
        return self.until(lambda line: 'info="done"' in line)

    def within(self, seconds: float) -> list[str]:
        """Every line that arrives in the next ``seconds`` s."""
        return self._collect(time.monotonic() + seconds)

    def to_eof(self, timeout: float = DEADLINE) -> list[str]:
        """The lines left until the server closes (a reset counts as closed)."""
        return self._collect(time.monotonic() + timeout, until_closed=True)

    def _collect(self, deadline: float, *, until_closed: bool = False) -> list[str]:
        lines: list[str] = []
        while True:
            try:
                line = self._line(deadline)
            except TimeoutError:
                if until_closed:
                    raise
                return lines
            except ConnectionResetError:
                if not until_closed:
                    raise
                return lines
            if line is None:
                return lines
            lines.append(line)

    def close(self) -> None:
        self.sock.close()

    def _line(self, deadline: float) -> str | None:
        while True:
            newline = self._buffer.find(b'\n')
            if newline >= 0:
                line = bytes(self._buffer[:newline]).decode('utf-8', errors='replace')
                del self._buffer[:newline + 1]
                return line
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError('no line in time')
            self.sock.settimeout(left)
            try:
                data = self.sock.recv(65536)
            except socket.timeout:
                raise TimeoutError('no line in time') from None
            if not data:
                return None
            self._buffer += data
