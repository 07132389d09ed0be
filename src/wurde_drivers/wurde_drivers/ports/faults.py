"""What went wrong on a serial line, told apart so that each kind is counted and handled as it is.

pyserial reports trouble in three shapes (a ``SerialException`` wrapping an ``OSError`` or
``termios.error``, a bare ``OSError``, a bare ``termios.error``); :func:`classify` finds the errno
in any of them and names the kind of fault: ``WOULD_BLOCK`` (nothing can move now: retried, the
port stays open), ``IO_ERROR`` and ``VANISHED`` (the port is closed and reopened after
``retry_s``), ``REFUSED`` (a setting is neither made nor recorded), ``OTHER``.
docs/wurde-drivers.md ("ports.faults") gives the errno table.

What is not a port error — a ``TypeError``, pyserial's ``PortNotOpenError`` (our own bug: using a
port we closed), any other exception — is not classified: :func:`is_port_error` says so, and the
link lets it propagate.  Keep it so: a programming error must not be retried as a line fault.
"""

from __future__ import annotations

import enum
import errno
import termios

import serial

__all__ = ['Fault', 'classify', 'error_number', 'is_port_error']


class Fault(enum.Enum):
    """The kind of trouble a serial port call ran into (see the module's table)."""

    WOULD_BLOCK = 'would block'
    IO_ERROR = 'I/O error'
    VANISHED = 'vanished'
    REFUSED = 'refused'
    OTHER = 'other'


_WOULD_BLOCK = {errno.EAGAIN, errno.EWOULDBLOCK, errno.EINTR, errno.EINPROGRESS, errno.EALREADY}
_VANISHED = {errno.ENXIO, errno.ENODEV, errno.ENOENT}
_REFUSED = {errno.EINVAL, errno.ENOTTY, errno.EOPNOTSUPP}
#: pyserial's words for a read that found the end of the file (it keeps no errno).
_END_OF_FILE = 'returned no data'


def _chain(error: BaseException) -> list[BaseException]:
    """``error`` and what it was raised from or during, outermost first (no cycles)."""
    out: list[BaseException] = []
    current: BaseException | None = error
    while current is not None and current not in out:
        out.append(current)
        current = current.__cause__ or current.__context__
    return out


def error_number(error: BaseException) -> int | None:
    """The errno behind ``error`` (an ``OSError``, a ``termios.error`` or what wraps them)."""
    for link in _chain(error):
        if isinstance(link, OSError) and isinstance(link.errno, int):
            return link.errno
        if isinstance(link, termios.error) and link.args and isinstance(link.args[0], int):
            return link.args[0]
    return None


def is_port_error(error: BaseException) -> bool:
    """True for what a failing port raises; False for our own bugs (they must propagate)."""
    if isinstance(error, serial.PortNotOpenError):
        return False
    return isinstance(error, (serial.SerialException, OSError, termios.error))


def classify(error: BaseException) -> Fault:
    """The :class:`Fault` ``error`` (a port error, see :func:`is_port_error`) stands for."""
    if isinstance(error, serial.SerialTimeoutException):
        return Fault.WOULD_BLOCK
    if any(_END_OF_FILE in str(link) for link in _chain(error)):
        return Fault.VANISHED
    number = error_number(error)
    if number in _WOULD_BLOCK:
        return Fault.WOULD_BLOCK
    if number == errno.EIO:
        return Fault.IO_ERROR
    if number in _VANISHED:
        return Fault.VANISHED
    if number in _REFUSED:
        return Fault.REFUSED
    return Fault.OTHER
