"""The port layer of the serial drivers: a pyserial URL opened, read and reopened, with counters.

A port is a pyserial URL (pyserial's ``serial_for_url``), so ``/dev/ttyS0``, a pty path from an
emulator and ``loop://`` all work (STYLE: transport chosen by URL). :class:`SerialLink` never raises
on a read: a vanished device is closed, counted and reopened on the next call after ``retry_s``,
so a driver's loop keeps running and can report the device as silent.
"""

from __future__ import annotations

import dataclasses
import termios
import time

import serial

from ..errors import DeviceError


@dataclasses.dataclass
class LinkStats:
    """What happened on a link: bytes, telegrams, and every kind of trouble, counted."""

    bytes_in: int = 0
    bytes_out: int = 0
    telegrams: int = 0
    bad_crc: int = 0
    bytes_skipped: int = 0      # garbage between frames, dropped while resynchronising
    timeouts: int = 0
    disconnects: int = 0
    reconnects: int = 0

    def as_dict(self) -> dict[str, int]:
        return dataclasses.asdict(self)


class SerialLink:
    """One serial device at ``url``; opened on demand, reopened after it vanishes.

    :param url: a pyserial URL or device path.
    :param baudrate: the initial line speed.
    :param parity: ``serial.PARITY_NONE`` or ``serial.PARITY_EVEN`` (SICK PLS); set at construction,
        because changing parity on an open pty fails (PROTOCOLS.md 6).
    :param retry_s: least time between two attempts to reopen a vanished device.
    """

    def __init__(self, url: str, baudrate: int, *, parity: str = serial.PARITY_NONE,
                 retry_s: float = 0.5) -> None:
        self.url = url
        self.baudrate = baudrate
        self.parity = parity
        self.retry_s = retry_s
        self.stats = LinkStats()
        self._port: serial.SerialBase | None = None
        self._next_try = 0.0

    @property
    def is_open(self) -> bool:
        return self._port is not None

    def open(self) -> None:
        """Open the port now.

        :raises DeviceError: the device cannot be opened (the pyserial error is chained).
        """
        if self._port is not None:
            return
        try:
            port = serial.serial_for_url(self.url, baudrate=self.baudrate, parity=self.parity,
                                         timeout=0, write_timeout=1.0)
        except (serial.SerialException, OSError, ValueError) as error:
            raise DeviceError(f'{self.url}: cannot open: {error}') from error
        self._port = port

    def _ensure_open(self) -> bool:
        if self._port is not None:
            return True
        now = time.monotonic()
        if now < self._next_try:
            return False
        self._next_try = now + self.retry_s
        try:
            self.open()
        except DeviceError:
            return False
        self.stats.reconnects += 1
        return True

    def _lost(self) -> None:
        self.stats.disconnects += 1
        self.close()
        self._next_try = time.monotonic() + self.retry_s

    def set_baudrate(self, baudrate: int) -> None:
        """Change the line speed (the device must have been told first)."""
        self.baudrate = baudrate
        if self._port is not None:
            try:
                self._port.baudrate = baudrate
            except termios.error:
                # A pty opened with even parity refuses a speed change (EINVAL, PROTOCOLS.md 6);
                # the line keeps its old speed, which a real port would have changed.
                pass
            except (serial.SerialException, OSError, ValueError):
                self._lost()

    def read(self, timeout: float) -> bytes:
        """Whatever arrives within ``timeout`` seconds (at least one byte, or b'' at the deadline).

        With the device gone this still waits out ``timeout``, so a poll loop does not spin.
        """
        if not self._ensure_open():
            time.sleep(max(0.0, timeout))
            return b''
        assert self._port is not None
        try:
            if self._port.timeout != timeout:   # each change is a tcsetattr system call
                self._port.timeout = timeout
            first = self._port.read(1)
            if not first:
                return b''
            waiting = self._port.in_waiting
            data = first + (self._port.read(waiting) if waiting else b'')
        except (serial.SerialException, OSError, TypeError, termios.error):
            self._lost()
            return b''
        self.stats.bytes_in += len(data)
        return data

    def write(self, data: bytes) -> bool:
        """Send ``data``; False if the device is not there (counted as a disconnect)."""
        if not self._ensure_open():
            return False
        assert self._port is not None
        try:
            self._port.write(data)
            self._port.flush()
        except (serial.SerialException, OSError):
            self._lost()
            return False
        self.stats.bytes_out += len(data)
        return True

    def reset_input(self) -> None:
        """Drop whatever is waiting to be read."""
        if self._port is not None:
            try:
                self._port.reset_input_buffer()
            except (serial.SerialException, OSError):
                self._lost()

    def close(self) -> None:
        """Close the port (idempotent)."""
        port, self._port = self._port, None
        if port is not None:
            try:
                port.close()
            except (serial.SerialException, OSError):
                pass

    def __enter__(self) -> 'SerialLink':
        self.open()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
