"""The port layer of the serial drivers: a pyserial URL opened, read and reopened, with counters.

A port is a pyserial URL (pyserial's ``serial_for_url``), so ``/dev/ttyS0``, a pty path from an
emulator and ``loop://`` all work (docs/style.md: transport chosen by URL). :class:`SerialLink` never raises
on a read or write that the *port* fails; what failed is told apart (:mod:`.faults`) and handled
as it is:

- nothing can move now (EAGAIN, a write timeout): counted in ``would_block``; the port stays open
  and the caller simply tries again later;
- the line failed (EIO) or the device vanished (ENXIO, ENODEV, end of file): counted in
  ``io_errors`` or ``vanished`` and in ``disconnects``; the port is closed and reopened on the
  next call after ``retry_s``, so a driver's loop keeps running and can report the device silent;
- a setting the port refuses (a line speed): :meth:`SerialLink.set_baudrate` raises and the
  recorded speed stays the old one (counted in ``refused``);
- a programming error (a ``TypeError``, using a port we closed) is not a port error: it propagates.

The last fault and its message stay in :attr:`SerialLink.last_fault` / :attr:`SerialLink.last_error`
for a module to log.
"""

from __future__ import annotations

import dataclasses
import io
import termios
import time
from typing import NoReturn

import serial

from ..errors import DeviceError
from .faults import Fault, classify, is_port_error
from .retry import RetryGate

#: What a failing pyserial port raises (sorted further by :func:`.faults.is_port_error`).
_PORT_ERRORS = (serial.SerialException, OSError, termios.error)


@dataclasses.dataclass
class LinkStats:
    """What happened on a link: bytes, telegrams, and every kind of trouble, counted.

    ``disconnects`` counts every time the port was closed because it failed; ``io_errors``,
    ``vanished`` and ``other_errors`` say why (each disconnect is in exactly one of them).
    """

    bytes_in: int = 0
    bytes_out: int = 0
    telegrams: int = 0
    bad_crc: int = 0
    bytes_skipped: int = 0      # garbage between frames, dropped while resynchronising
    timeouts: int = 0
    disconnects: int = 0
    reconnects: int = 0
    would_block: int = 0        # EAGAIN or a write timeout: nothing moved, the port stays open
    io_errors: int = 0          # disconnects after EIO
    vanished: int = 0           # disconnects after ENXIO/ENODEV/ENOENT or end of file
    other_errors: int = 0       # disconnects after any other port error
    refused: int = 0            # settings (line speeds) the port refused
    open_failures: int = 0      # attempts to reopen that failed

    def as_dict(self) -> dict[str, int]:
        return dataclasses.asdict(self)


#: The counter of each fault that closes the port.
_DISCONNECT_COUNTERS = {Fault.IO_ERROR: 'io_errors', Fault.VANISHED: 'vanished',
                        Fault.REFUSED: 'other_errors', Fault.OTHER: 'other_errors'}


class SerialLink:
    """One serial device at a URL; opened on demand, reopened after it vanishes."""

    def __init__(self, url: str, baudrate: int, *, parity: str = serial.PARITY_NONE,
                 retry_s: float = 0.5, write_timeout: float = 1.0) -> None:
        """Keep the settings; nothing is opened until :meth:`open` or the first read or write.

        :param url: a pyserial URL or device path.
        :param baudrate: the initial line speed.
        :param parity: ``serial.PARITY_NONE`` or ``serial.PARITY_EVEN`` (SICK PLS); set at construction,
            because changing parity on an open pty fails (docs/protocols.md 6).
        :param retry_s: least time between two attempts to reopen a vanished device.
        :param write_timeout: longest wait for the device to take a write's bytes (then the write
            fails as ``would_block``; the port stays open).
        """
        self._url = url
        self.baudrate = baudrate
        self.parity = parity
        self.retry_s = retry_s
        self.write_timeout = write_timeout
        self.stats = LinkStats()
        #: The kind of the last port error (None before any), and its message.
        self.last_fault: Fault | None = None
        self.last_error = ''
        self._port: serial.SerialBase | None = None
        self._retry = RetryGate(retry_s)

    @property
    def url(self) -> str:
        """Move to another device path (udev renamed it).

        A port open at the old path is closed, so that the next read opens the new one at once.  While
        the device was gone, the old path may have been given to another device (a pseudo-terminal
        number is reused at once): a link that kept that port would read the wrong device for ever.

        :param url: the new pyserial URL or device path.
        """
        return self._url

    @url.setter
    def url(self, url: str) -> None:
        """Move to another device path (udev renamed it): a port open at the old path is closed, so
        that the next read opens the new one at once.  While the device was gone, the old path may
        have been given to another device (a pseudo-terminal number is reused at once): a link that
        kept that port would read the wrong device for ever."""
        if url != self._url:
            self._url = url
            if self._port is not None:
                self.close()
            self._retry.at_once()

    @property
    def is_open(self) -> bool:
        return self._port is not None

    def fault_note(self) -> str:
        """``'; last port fault: ...'`` for a module's log line, or ``''`` if the port never
        failed: says whether a silent device vanished, hung up the line (EIO) or just says
        nothing."""
        return f'; last port fault: {self.last_error}' if self.last_error else ''

    def open(self) -> None:
        """Open the port now.

        :raises DeviceError: the device cannot be opened (the pyserial error is chained).
        """
        if self._port is not None:
            return
        try:
            port = serial.serial_for_url(self.url, baudrate=self.baudrate, parity=self.parity,
                                         timeout=0, write_timeout=self.write_timeout)
        except (serial.SerialException, OSError, ValueError) as error:
            if isinstance(error, _PORT_ERRORS):
                self._note(error, 'open')
            raise DeviceError(f'{self.url}: cannot open: {error}') from error
        self._port = port

    def _ensure_open(self) -> bool:
        if self._port is not None:
            return True
        if not self._retry.due(time.monotonic()):
            return False
        try:
            self.open()
        except DeviceError:
            self.stats.open_failures += 1
            return False
        self.stats.reconnects += 1
        return True

    def _note(self, error: BaseException, during: str) -> Fault:
        """Classify a port error and remember it; a programming error is raised again."""
        if not is_port_error(error):
            raise error
        fault = classify(error)
        self.last_fault = fault
        self.last_error = f'{self.url}: {during}: {fault.value}: {error}'
        return fault

    def _failed(self, error: BaseException, during: str) -> Fault:
        """Handle a port error of a read, write or flush: retry later, or close and reopen."""
        fault = self._note(error, during)
        if fault is Fault.WOULD_BLOCK:
            self.stats.would_block += 1
        else:
            self._lost(fault)
        return fault

    def _lost(self, fault: Fault) -> None:
        self.stats.disconnects += 1
        counter = _DISCONNECT_COUNTERS[fault]
        setattr(self.stats, counter, getattr(self.stats, counter) + 1)
        self.close()
        self._retry.later(time.monotonic())

    def set_baudrate(self, baudrate: int) -> None:
        """Change the line speed (the device must have been told first).

        The speed is recorded only once the port has it: the line is read back where it can
        be (a port that takes the request but keeps its old speed has refused it).  While the
        port is closed the speed is recorded for the next open, which applies it or fails.

        :param baudrate: the new speed.
        :raises TypeError: ``baudrate`` is not an int (a bug, not a port fault).
        :raises DeviceError: the port refused the speed (counted in ``refused``; the line keeps
            the old one and so does :attr:`baudrate`), or the port failed while changing it
            (counted as a disconnect; the port is closed, :attr:`baudrate` unchanged).
        """
        if not isinstance(baudrate, int) or isinstance(baudrate, bool):
            raise TypeError(f'baudrate must be an int, not {baudrate!r}')
        port = self._port
        if port is None:
            self.baudrate = baudrate
            return
        try:
            port.baudrate = baudrate
            taken = self._line_speed_is(port, baudrate)
        except _PORT_ERRORS as error:
            fault = self._note(error, f'set {baudrate} Bd')
            if fault is not Fault.REFUSED:
                self._lost(fault)
                raise DeviceError(self.last_error) from error
            self._refuse(port, baudrate, str(error), error)
        except (ValueError, OverflowError) as error:     # pyserial: a speed it cannot set
            self._refuse(port, baudrate, str(error), error)
        if not taken:
            self._refuse(port, baudrate, 'the line kept its old speed')
        self.baudrate = baudrate

    def _refuse(self, port: serial.SerialBase, baudrate: int, why: str,
                error: BaseException | None = None) -> NoReturn:
        """Count a refused speed, put the port's own idea of its speed back, and raise."""
        self.stats.refused += 1
        self.last_fault = Fault.REFUSED
        self.last_error = f'{self.url}: set {baudrate} Bd: refused: {why}'
        message = self.last_error
        try:
            port.baudrate = self.baudrate
        except _PORT_ERRORS as restore_error:
            self._lost(self._note(restore_error, f'restore {self.baudrate} Bd'))
        raise DeviceError(message) from error

    @staticmethod
    def _line_speed_is(port: serial.SerialBase, baudrate: int) -> bool:
        """Whether the line reports ``baudrate`` (True where it cannot be read back)."""
        expected = getattr(termios, f'B{baudrate}', None)
        try:
            fd = port.fileno()
        except (AttributeError, io.UnsupportedOperation):
            return True                      # loop:// and other URLs: no line to read back
        if expected is None or not isinstance(fd, int):
            return True                      # a custom speed (BOTHER): not readable this way
        return termios.tcgetattr(fd)[4] == expected

    def read(self, timeout: float) -> bytes:
        """Whatever arrives within ``timeout`` seconds (at least one byte, or b'' at the deadline).

        With the device gone this still waits out ``timeout``, so a poll loop does not spin — but
        it tries to reopen the device every ``retry_s`` meanwhile and reads from it once it is
        back: a read that slept out its whole timeout would miss a device that came back at once.

        :param timeout: the longest wait in seconds.
        """
        deadline = time.monotonic() + timeout
        wait = max(0.0, timeout)
        while True:
            if not self._ensure_open():
                now = time.monotonic()
                if now >= deadline:
                    return b''
                time.sleep(min(deadline - now, self._retry.wait_s(now)))
                wait = max(0.0, deadline - time.monotonic())
                continue
            assert self._port is not None
            try:
                if self._port.timeout != wait:      # each change is a termios round trip
                    self._port.timeout = wait
                first = self._port.read(1)
                if not first:
                    return b''
                waiting = self._port.in_waiting
                data = first + (self._port.read(waiting) if waiting else b'')
            except _PORT_ERRORS as error:
                if self._failed(error, 'read') is Fault.WOULD_BLOCK:
                    wait = deadline - time.monotonic()
                    if wait > 0:
                        continue                    # nothing to read now: try again in time
                return b''
            self.stats.bytes_in += len(data)
            return data

    def write(self, data: bytes) -> bool:
        """Send ``data``.

        :param data: the bytes to send; the write waits at most ``write_timeout`` for the device to take them.
        :returns: False if it could not go now (``would_block``: the port stays open) or the device
            is not there (counted as a disconnect).
        """
        if not self._ensure_open():
            return False
        assert self._port is not None
        try:
            self._port.write(data)
            self._port.flush()
        except _PORT_ERRORS as error:
            self._failed(error, 'write')
            return False
        self.stats.bytes_out += len(data)
        return True

    def reset_input(self) -> None:
        """Drop whatever is waiting to be read."""
        if self._port is not None:
            try:
                self._port.reset_input_buffer()
            except _PORT_ERRORS as error:
                self._failed(error, 'reset input')

    def close(self) -> None:
        """Close the port (idempotent)."""
        port, self._port = self._port, None
        if port is not None:
            try:
                port.close()
            except _PORT_ERRORS:
                pass                                # closing a port that failed: nothing to do

    def __enter__(self) -> 'SerialLink':
        self.open()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
