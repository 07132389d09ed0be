"""Reading a Linux joystick device (``/dev/input/js0``) or anything that carries its js_event
bytes: a FIFO the ``joystick_emulator`` writes, a pseudo-terminal in raw mode.

:class:`JoystickDriver` never blocks and never raises for the device's sake: :meth:`poll` opens
the path when it is not open (at most every ``retry_s`` seconds), reads whatever is there and
returns the decoded events.  It tells its states apart (:attr:`state`) and reports each change
once through ``report``:

- ``ABSENT``: the path cannot be opened (not there yet, no permission, unplugged); retried.
- ``WAITING``: open, nothing read yet (a FIFO whose writer has not come; a kernel joystick sends
  its init events at once, so it is WAITING only for an instant).
- ``LIVE``: bytes have come since the open.
- a device that vanishes — read error (ENODEV, EIO), end of file, or POLLHUP/POLLERR (a FIFO's
  writer gone, a pty's master closed) — is closed, counted in :attr:`vanished` and retried:
  ``ABSENT`` again until it reopens.

A reopened device starts on a record boundary, so a partial record is forgotten at each close.
"""

from __future__ import annotations

import enum
import errno
import os
import select
import time
from collections.abc import Callable

from ..ports.retry import RetryGate
from .codec import JsDecoder, JsEvent

__all__ = ['DeviceState', 'JoystickDevice', 'JoystickDriver']

_READ_BYTES = 64 * 8
#: Reads per :meth:`JoystickDriver.poll` at most: a flood never holds the caller's loop.
_MAX_READS = 16


class DeviceState(enum.Enum):
    ABSENT = 'absent'
    WAITING = 'waiting'
    LIVE = 'live'


class JoystickDriver:
    """The joystick at a device path.  Construct (no I/O), :meth:`poll` each loop, :meth:`close`."""

    def __init__(self, path: str, *, retry_s: float = 1.0,
                 report: Callable[[str], object] | None = None) -> None:
        """Keep the settings; the device is opened by :meth:`poll`.

        :param path: the device, e.g. ``/dev/input/js0``.
        :param retry_s: least time between two attempts to open an absent device.
        :param report: called with a one-line message at each change of state.
        """
        self.path = path
        self.retry_s = retry_s
        self.report = report or (lambda message: None)
        self.decoder = JsDecoder()
        self.state = DeviceState.ABSENT
        self.opens = 0
        self.vanished = 0
        self._fd = -1
        self._poller: select.poll | None = None
        self._retry = RetryGate(retry_s)
        self._absent_reason = ''

    @property
    def dropped(self) -> int:
        """Records of an unknown type dropped (see :class:`~.codec.JsDecoder`)."""
        return self.decoder.dropped

    def poll(self, now: float | None = None) -> list[JsEvent]:
        """Open if due, then read without blocking; the events that came (maybe none).

        :param now: ``time.monotonic()``; None reads the clock.
        """
        now = time.monotonic() if now is None else now
        if self._fd < 0 and not self._open(now):
            return []
        events: list[JsEvent] = []
        assert self._poller is not None
        for _ in range(_MAX_READS):
            ready = self._poller.poll(0)
            if not ready:
                break
            mask = ready[0][1]
            if mask & select.POLLIN:
                try:
                    data = os.read(self._fd, _READ_BYTES)
                except BlockingIOError:
                    break
                except OSError as error:
                    self._vanish(now, os.strerror(error.errno or errno.EIO))
                    break
                if not data:
                    self._vanish(now, 'end of file')
                    break
                if self.state != DeviceState.LIVE:
                    self._set(DeviceState.LIVE, f'joystick {self.path}: live')
                events.extend(self.decoder.feed(data))
                continue
            if mask & (select.POLLHUP | select.POLLERR | select.POLLNVAL):
                self._vanish(now, 'hung up')
            break
        return events

    def close(self) -> None:
        """Close the device (idempotent); a later :meth:`poll` opens it again."""
        if self._fd >= 0:
            try:
                os.close(self._fd)
            except OSError:
                pass
        self._fd = -1
        self._poller = None
        self.decoder.reset()

    # -- internals -------------------------------------------------------------------------------
    def _open(self, now: float) -> bool:
        if not self._retry.due(now):
            return False
        try:
            fd = os.open(self.path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | os.O_NOCTTY)
        except OSError as error:
            reason = error.strerror or str(error)
            if reason != self._absent_reason or self.state != DeviceState.ABSENT:
                self._absent_reason = reason
                self._set(DeviceState.ABSENT, f'joystick {self.path}: not there ({reason}); '
                                              f'retrying every {self.retry_s:g} s')
            return False
        self._fd = fd
        self._poller = select.poll()
        self._poller.register(fd, select.POLLIN)
        self.opens += 1
        self._absent_reason = ''
        self._set(DeviceState.WAITING, f'joystick {self.path}: opened, waiting for events')
        return True

    def _vanish(self, now: float, reason: str) -> None:
        self.close()
        self.vanished += 1
        self._retry.at_once()           # a device that comes straight back is reopened at once
        self._absent_reason = ''
        self._set(DeviceState.ABSENT, f'joystick {self.path}: gone ({reason})')

    def _set(self, state: DeviceState, message: str) -> None:
        self.state = state
        self.report(message)


JoystickDevice = JoystickDriver  # old name (docs/naming.md)
