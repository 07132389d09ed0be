"""An emulated joystick: real js_event bytes into a FIFO, as the kernel writes them to
``/dev/input/js0``.

:class:`JoystickEmulator` makes a FIFO at ``path`` and holds the state of its axes and buttons.
Like the kernel, it greets every reader that opens the device with one init event
(``JS_EVENT_INIT``) per axis and button carrying the current state, then sends each change as it
happens.  A reader that goes away is noticed (POLLERR on the writing end, or EPIPE) and the
emulator waits for the next one, which gets its own init events; changes made while no reader
is there are not queued (the kernel does not either), they are in the next init events.
A FIFO's writer learns that its reader closed only by looking (every ``tick_s``): a reader that
closes and reopens within that time shares the old pipe and gets no new init events.
:meth:`stop` closes the writing end, so the reader sees the device vanish, and removes the FIFO.

One thread writes; :meth:`set_axis` and :meth:`set_button` may be called from any thread.
"""

from __future__ import annotations

import collections
import errno
import os
import select
import stat
import threading
import time

from ..errors import DriverError
from .codec import AXIS_MAX, EVENT_SIZE, JS_EVENT_AXIS, JS_EVENT_BUTTON, JsEvent, encode_event

#: Events per write: a FIFO write of at most PIPE_BUF bytes is atomic (all or EAGAIN, never part).
_EVENTS_PER_WRITE = select.PIPE_BUF // EVENT_SIZE

__all__ = ['JoystickEmulator']


class JoystickEmulator:
    """A joystick with ``axes`` axes and ``buttons`` buttons on a FIFO at ``path``.

    Use as a context manager, or :meth:`start` and :meth:`stop` (idempotent).

    :raises DriverError: from :meth:`start` when ``path`` exists and is not a FIFO.
    """

    def __init__(self, path: str, *, axes: int = 8, buttons: int = 12, tick_s: float = 0.01) -> None:
        self.path = path
        self.tick_s = tick_s
        self._axes = [0] * axes
        self._buttons = [0] * buttons
        self._queue: collections.deque[JsEvent] = collections.deque()
        self._lock = threading.Condition()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name='JoystickEmulator', daemon=True)
        self._fd = -1
        self._made_fifo = False
        self._t0 = time.monotonic()
        #: Readers greeted so far (each open of the device by a reader counts once).
        self.connections = 0
        #: Readers seen leaving.
        self.disconnects = 0
        #: Events lost because the reader did not read (its pipe was full).
        self.dropped = 0
        self.events_sent = 0
        self.error: BaseException | None = None

    # -- life cycle ---------------------------------------------------------------------------
    def start(self) -> 'JoystickEmulator':
        try:
            mode = os.stat(self.path).st_mode
        except FileNotFoundError:
            os.mkfifo(self.path, 0o660)
            self._made_fifo = True
        else:
            if not stat.S_ISFIFO(mode):
                raise DriverError(f'{self.path} exists and is not a FIFO')
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        with self._lock:
            self._lock.notify_all()
        if self._thread.is_alive() and threading.current_thread() is not self._thread:
            self._thread.join(timeout=5.0)
        self._close()
        if self._made_fifo:
            try:
                os.unlink(self.path)
            except FileNotFoundError:
                pass
            self._made_fifo = False

    def __enter__(self) -> 'JoystickEmulator':
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- the stick ----------------------------------------------------------------------------
    @property
    def axes(self) -> int:
        return len(self._axes)

    @property
    def buttons(self) -> int:
        return len(self._buttons)

    @property
    def connected(self) -> bool:
        """Whether a reader has the device open."""
        return self._fd >= 0

    def set_axis(self, number: int, value: int) -> None:
        """Move axis ``number`` to ``value`` (-32767 .. 32767).

        :raises ValueError: no such axis, or the value is out of range.
        """
        if not 0 <= number < len(self._axes):
            raise ValueError(f'axis {number}: the joystick has axes 0 to {len(self._axes) - 1}')
        if not -AXIS_MAX <= value <= AXIS_MAX:
            raise ValueError(f'axis value {value} is not within -{AXIS_MAX} .. {AXIS_MAX}')
        self._change(JS_EVENT_AXIS, number, int(value), self._axes)

    def set_button(self, number: int, pressed: bool) -> None:
        """Press (True) or release button ``number``.

        :raises ValueError: no such button.
        """
        if not 0 <= number < len(self._buttons):
            raise ValueError(f'button {number}: the joystick has buttons 0 to {len(self._buttons) - 1}')
        self._change(JS_EVENT_BUTTON, number, 1 if pressed else 0, self._buttons)

    def wait_connected(self, count: int = 1, timeout: float = 10.0) -> bool:
        """Wait until ``count`` readers have been greeted in all; whether they were in time."""
        with self._lock:
            return self._lock.wait_for(lambda: self.connections >= count or self.error is not None,
                                       timeout) and self.connections >= count

    def wait_disconnected(self, count: int = 1, timeout: float = 10.0) -> bool:
        """Wait until ``count`` readers have been seen leaving in all; whether they were in time."""
        with self._lock:
            return self._lock.wait_for(lambda: self.disconnects >= count or self.error is not None,
                                       timeout) and self.disconnects >= count

    def wait_sent(self, timeout: float = 10.0) -> bool:
        """Wait until every change made so far is written (or dropped for want of a reader)."""
        with self._lock:
            return self._lock.wait_for(lambda: not self._queue, timeout)

    # -- internals --------------------------------------------------------------------------------
    def _now_ms(self) -> int:
        return int((time.monotonic() - self._t0) * 1000.0) & 0xFFFFFFFF

    def _change(self, kind: int, number: int, value: int, state: list[int]) -> None:
        with self._lock:
            if state[number] == value:
                return
            state[number] = value
            if self._fd >= 0:
                self._queue.append(JsEvent(kind, number, value, self._now_ms()))
            self._lock.notify_all()

    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                if self._fd < 0:
                    self._connect()
                    if self._fd < 0:
                        self._stop.wait(self.tick_s)
                        continue
                self._check_reader()
                self._flush()
                with self._lock:
                    if not self._queue and not self._stop.is_set():
                        self._lock.wait(self.tick_s)
        except BaseException as error:   # kept for the owner to see; the thread must not die silently
            self.error = error
            with self._lock:
                self._lock.notify_all()
            raise

    def _connect(self) -> None:
        try:
            fd = os.open(self.path, os.O_WRONLY | os.O_NONBLOCK | os.O_CLOEXEC)
        except OSError as error:
            if error.errno in (errno.ENXIO, errno.ENOENT):
                return            # no reader yet (or the FIFO was removed under us: wait)
            raise
        with self._lock:
            self._fd = fd
            now = self._now_ms()
            self._queue.clear()
            self._queue.extend(JsEvent(JS_EVENT_AXIS, n, v, now, init=True)
                               for n, v in enumerate(self._axes))
            self._queue.extend(JsEvent(JS_EVENT_BUTTON, n, v, now, init=True)
                               for n, v in enumerate(self._buttons))
            self.connections += 1
            self._lock.notify_all()

    def _check_reader(self) -> None:
        poller = select.poll()
        poller.register(self._fd, 0)    # POLLERR is always reported: the reader has gone
        if poller.poll(0):
            self._reader_gone()

    def _flush(self) -> None:
        """Write what is queued, as many events at once as one atomic FIFO write holds: a
        reader gets the init events of its open in one read, as from the kernel (whose read
        makes them all at once).  Written one by one, a reader on a loaded machine can take the
        first axis's init event as the whole state (the other axes then read 0)."""
        while True:
            with self._lock:
                if not self._queue or self._fd < 0:
                    self._lock.notify_all()
                    return
                batch = [self._queue.popleft()
                         for _ in range(min(len(self._queue), _EVENTS_PER_WRITE))]
            try:
                os.write(self._fd, b''.join(encode_event(event) for event in batch))
                self.events_sent += len(batch)
            except BlockingIOError:
                self.dropped += len(batch)
            except BrokenPipeError:
                self._reader_gone()

    def _reader_gone(self) -> None:
        self._close()
        with self._lock:
            self.disconnects += 1
            self._queue.clear()
            self._lock.notify_all()

    def _close(self) -> None:
        with self._lock:
            fd, self._fd = self._fd, -1
        if fd >= 0:
            try:
                os.close(fd)
            except OSError:
                pass
