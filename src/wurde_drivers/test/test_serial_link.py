"""SerialLink's errors tell the truth: each kind of port trouble on a real pseudo-terminal is
counted as what it is and handled as it must be (issue 10, section 5).

- EAGAIN (nothing can move now): retried, never a disconnect (on a read, pyserial's posix port
  retries EAGAIN itself, so the link meets it only on a write: a full line);
- EIO (the line failed) and a vanished device (end of file, node gone): disconnect and reopen,
  counted apart;
- a speed the port refuses: raised, and the recorded speed stays the old one;
- a programming error (TypeError): propagates, not counted as anything.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import os
import struct
import termios
import time
import tty
from collections.abc import Iterator

import pytest
import serial

from wurde_drivers.errors import DeviceError
from wurde_drivers.ports.faults import Fault, classify, error_number, is_port_error
from wurde_drivers.ports.serial_link import SerialLink

#: Linux's "lock these termios bits" ioctl (tty_ioctl(4)); needs CAP_SYS_ADMIN.
TIOCSLCKTRMIOS = 0x5457


class Pty:
    """A bare pseudo-terminal: the test holds the master (the device), the link opens ``path``."""

    def __init__(self) -> None:
        self.master, self.slave = os.openpty()
        tty.setraw(self.master)
        self.path = os.ttyname(self.slave)

    def speed(self) -> int:
        return termios.tcgetattr(self.slave)[4]

    def close_master(self) -> None:
        """The device's end goes away: Linux hangs the slave up (EOF on read, EIO elsewhere)."""
        if self.master >= 0:
            os.close(self.master)
            self.master = -1

    def close(self) -> None:
        self.close_master()
        if self.slave >= 0:
            os.close(self.slave)
            self.slave = -1


@pytest.fixture
def pty() -> Iterator[Pty]:
    device = Pty()
    try:
        yield device
    finally:
        device.close()


@pytest.fixture
def link(pty: Pty) -> Iterator[SerialLink]:
    port = SerialLink(pty.path, 9600, retry_s=0.05)
    port.open()
    try:
        yield port
    finally:
        port.close()


def troubles(link: SerialLink) -> dict[str, int]:
    stats = link.stats
    return {name: getattr(stats, name) for name in (
        'would_block', 'io_errors', 'vanished', 'other_errors', 'refused', 'disconnects')}


NONE = dict.fromkeys(('would_block', 'io_errors', 'vanished', 'other_errors', 'refused',
                      'disconnects'), 0)


# -- the classification, on the exceptions pyserial really raises ---------------------------------
def test_errors_are_classified_by_their_errno() -> None:
    def wrapped(number: int) -> serial.SerialException:
        try:
            try:
                raise OSError(number, os.strerror(number))
            except OSError as inner:
                raise serial.SerialException(f'read failed: {inner}')   # pyserial's shape
        except serial.SerialException as outer:
            return outer

    assert classify(wrapped(errno.EAGAIN)) is Fault.WOULD_BLOCK
    assert classify(wrapped(errno.EIO)) is Fault.IO_ERROR
    assert classify(wrapped(errno.ENXIO)) is Fault.VANISHED
    assert classify(wrapped(errno.ENODEV)) is Fault.VANISHED
    assert classify(termios.error(errno.EIO, 'Input/output error')) is Fault.IO_ERROR
    assert classify(termios.error(errno.EINVAL, 'Invalid argument')) is Fault.REFUSED
    assert classify(serial.SerialTimeoutException('Write timeout')) is Fault.WOULD_BLOCK
    assert classify(serial.SerialException('device reports readiness to read but returned no '
                                           'data (device disconnected ...)')) is Fault.VANISHED
    assert classify(wrapped(errno.EPROTO)) is Fault.OTHER
    assert error_number(wrapped(errno.EIO)) == errno.EIO
    assert not is_port_error(TypeError('bug')) and not is_port_error(serial.PortNotOpenError())


# -- EAGAIN: nothing can move now ---------------------------------------------------------------
def test_a_full_line_is_would_block_not_a_disconnect(pty: Pty) -> None:
    """The device reads nothing: the pty's buffer fills (EAGAIN) until the write times out."""
    link = SerialLink(pty.path, 9600, write_timeout=0.2)
    link.open()
    try:
        chunk = b'x' * 4096
        deadline = time.monotonic() + 30.0
        while link.write(chunk):
            assert time.monotonic() < deadline, 'the pty never filled up'
        assert troubles(link) == dict(NONE, would_block=1)
        assert link.is_open and link.last_fault is Fault.WOULD_BLOCK
        os.set_blocking(pty.master, False)   # the device reads everything: the line moves again
        drained = 0
        with contextlib.suppress(BlockingIOError):
            while True:
                drained += len(os.read(pty.master, 65536))
        assert drained > 0
        assert link.write(b'PP100 ')
        assert troubles(link) == dict(NONE, would_block=1)
    finally:
        link.close()


# -- EIO and a vanished device: disconnect, reopen, counted apart -------------------------------
def test_eio_on_write_after_the_device_end_closed_is_an_io_error(pty: Pty,
                                                                   link: SerialLink) -> None:
    assert link.write(b'hello')
    pty.close_master()
    assert not link.write(b'again')
    assert troubles(link) == dict(NONE, io_errors=1, disconnects=1)
    assert link.last_fault is Fault.IO_ERROR and 'write' in link.last_error
    assert not link.is_open
    assert link.fault_note().startswith('; last port fault: ') and 'I/O error' in link.fault_note()


def test_end_of_file_on_read_is_a_vanished_device(pty: Pty, link: SerialLink) -> None:
    assert link.read(0.05) == b''            # the port's read timeout is now 0.05 s
    pty.close_master()
    start = time.monotonic()
    assert link.read(0.05) == b''            # ready to read, yet nothing: a hung-up line
    assert time.monotonic() - start < 5.0
    assert troubles(link) == dict(NONE, vanished=1, disconnects=1)
    assert link.last_fault is Fault.VANISHED and not link.is_open


def test_a_vanished_device_is_reopened_when_it_comes_back(pty: Pty, link: SerialLink) -> None:
    pty.close()                              # the node is gone for good
    assert link.read(0.05) == b''
    assert link.stats.disconnects == 1
    deadline = time.monotonic() + 20.0
    while link.stats.open_failures == 0:     # a reopen is tried (after retry_s) and fails
        assert time.monotonic() < deadline, 'no reopen was tried'
        assert link.read(0.05) == b''
    assert link.last_fault is Fault.VANISHED and 'open' in link.last_error
    replacement = Pty()                      # ... and comes back (udev may rename it)
    try:
        link.url = replacement.path
        while not link.is_open:              # (opening flushes what was waiting)
            assert time.monotonic() < deadline, 'the device that came back was not reopened'
            assert link.read(0.05) == b''
        os.write(replacement.master, b'$')
        data = b''
        while not data:
            assert time.monotonic() < deadline, 'the device that came back was not read'
            data = link.read(0.1)
        assert data == b'$' and link.stats.reconnects == 1
        assert troubles(link)['disconnects'] == 1
    finally:
        link.close()
        replacement.close()


# -- a refused speed is reported, never recorded --------------------------------------------------
def test_a_speed_pyserial_refuses_is_raised_and_not_recorded(pty: Pty, link: SerialLink) -> None:
    with pytest.raises(DeviceError, match='refused'):
        link.set_baudrate(-9600)
    assert link.baudrate == 9600 and pty.speed() == termios.B9600
    assert troubles(link) == dict(NONE, refused=1)
    assert link.is_open and link.last_fault is Fault.REFUSED
    link.set_baudrate(38400)                 # a good speed still goes through
    assert link.baudrate == 38400 and pty.speed() == termios.B38400


def test_a_speed_the_line_does_not_take_is_raised_and_not_recorded(pty: Pty,
                                                                    link: SerialLink) -> None:
    """The port accepts the request but keeps its speed (here: the speed bits are locked, as a
    fixed-speed line would): read back, the change did not happen."""
    lock = struct.pack('4IB19s', 0, 0, termios.CBAUD | getattr(termios, 'CBAUDEX', 0), 0, 0,
                       bytes(19))
    try:
        fcntl.ioctl(pty.slave, TIOCSLCKTRMIOS, lock)
    except OSError as error:
        pytest.skip(f'cannot lock the line speed here (needs CAP_SYS_ADMIN): {error}')
    with pytest.raises(DeviceError, match='kept its old speed'):
        link.set_baudrate(38400)
    assert link.baudrate == 9600 and pty.speed() == termios.B9600
    assert troubles(link) == dict(NONE, refused=1) and link.is_open


def test_a_speed_change_on_a_failed_line_is_a_disconnect(pty: Pty, link: SerialLink) -> None:
    pty.close_master()
    with pytest.raises(DeviceError):
        link.set_baudrate(38400)
    assert link.baudrate == 9600 and not link.is_open
    assert troubles(link) == dict(NONE, io_errors=1, disconnects=1)


def test_a_speed_set_while_closed_is_what_the_next_open_uses(pty: Pty) -> None:
    link = SerialLink(pty.path, 9600)
    link.set_baudrate(19200)
    try:
        link.open()
        assert link.baudrate == 19200 and pty.speed() == termios.B19200
    finally:
        link.close()


# -- programming errors propagate ------------------------------------------------------------------
def test_a_type_error_is_a_bug_not_a_disconnect(pty: Pty, link: SerialLink) -> None:
    with pytest.raises(TypeError):
        link.write('PP100 ')                 # type: ignore[arg-type]  # str, not bytes
    with pytest.raises(TypeError):
        link.set_baudrate('9600')            # type: ignore[arg-type]
    with pytest.raises(TypeError):
        link.read('soon')                    # type: ignore[arg-type]
    assert troubles(link) == NONE and link.is_open and link.last_fault is None
    assert link.write(b'still fine') and os.read(pty.master, 64) == b'still fine'
    assert link.fault_note() == ''


def test_a_new_path_is_read_at_once_even_while_the_old_port_is_open(pty: Pty, link: SerialLink) -> None:
    """udev renamed the device (or it came back elsewhere) while the old path was given to another
    device — a pseudo-terminal number is reused at once: the link must leave the old port, not go
    on reading a stranger (a loaded CI run read nothing for 20 s so)."""
    other = Pty()
    try:
        link.url = other.path
        assert link.read(0.1) == b''           # opens the new path (pyserial flushes what waited)
        os.write(pty.master, b'stranger')
        os.write(other.master, b'device')
        deadline, got = time.monotonic() + 10.0, b''
        while len(got) < 6 and time.monotonic() < deadline:
            got += link.read(0.2)
        assert got == b'device' and link.stats.reconnects >= 1
    finally:
        other.close()
