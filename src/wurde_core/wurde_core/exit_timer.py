"""A timer that ends the process with a given status from C, for a program on its way out.

A quitting module's last step is the DDS teardown (its node's and participant's deletion).  On a
loaded machine Fast DDS can take more than 2 s there, inside one C call that holds the GIL: no
Python thread, signal handler or ``threading.Timer`` runs until it returns.  The only ways out that
need no Python are C-level: faulthandler's timer (which can only exit with status 1) and a POSIX
timer whose expiry runs a C function in a thread of its own — here libc's ``_exit`` with the status
as its argument (``timer_create`` with ``SIGEV_THREAD``).  By then the module has said goodbye and
released its own resources; what is abandoned is the middleware's deletion of sockets and shared
memory, which the kernel releases at the exit (as after the SIGKILL the MCP would send at 4 s), and
remote participants drop ours at its lease's end.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import time

__all__ = ['ExitTimer']

_CLOCK_MONOTONIC = 1
_SIGEV_THREAD = 2


class _SigEvent(ctypes.Structure):
    """``struct sigevent`` of Linux (64 bytes): value, signo, notify, then the union whose
    ``_sigev_thread`` member holds the function and its thread attributes."""

    _fields_ = [('sigev_value', ctypes.c_void_p), ('sigev_signo', ctypes.c_int),
                ('sigev_notify', ctypes.c_int), ('sigev_notify_function', ctypes.c_void_p),
                ('sigev_notify_attributes', ctypes.c_void_p),
                ('_pad', ctypes.c_int * 8)]


class _TimeSpec(ctypes.Structure):
    _fields_ = [('tv_sec', ctypes.c_long), ('tv_nsec', ctypes.c_long)]


class _ITimerSpec(ctypes.Structure):
    _fields_ = [('it_interval', _TimeSpec), ('it_value', _TimeSpec)]


_libc = ctypes.CDLL(ctypes.util.find_library('c') or 'libc.so.6', use_errno=True)
_libc.timer_create.argtypes = [ctypes.c_int, ctypes.POINTER(_SigEvent), ctypes.POINTER(ctypes.c_void_p)]
_libc.timer_settime.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.POINTER(_ITimerSpec), ctypes.c_void_p]
_libc.timer_delete.argtypes = [ctypes.c_void_p]


class ExitTimer:
    """``ExitTimer(seconds, status)`` arms a one-shot timer that calls ``_exit(status)`` after
    ``seconds`` of the monotonic clock, whatever the process is doing then; ``cancel()`` disarms
    and frees it (idempotent).  Nothing is flushed at that exit: write what must be kept first."""

    def __init__(self, seconds: float, status: int) -> None:
        """Arm the timer.

        :param seconds: the delay, monotonic clock.
        :param status: the process's exit status then.
        :raises OSError: when the system refuses the timer.
        """
        self._timer = ctypes.c_void_p()
        event = _SigEvent()
        # sigev_value is the function's argument: a union of int and pointer, passed as the
        # integer register _exit reads its status from.
        event.sigev_value = status
        event.sigev_notify = _SIGEV_THREAD
        event.sigev_notify_function = ctypes.cast(_libc._exit, ctypes.c_void_p).value
        if _libc.timer_create(_CLOCK_MONOTONIC, ctypes.byref(event), ctypes.byref(self._timer)) != 0:
            raise OSError(ctypes.get_errno(), 'timer_create failed')
        self.deadline = time.monotonic() + seconds
        whole = int(seconds)
        spec = _ITimerSpec(_TimeSpec(0, 0), _TimeSpec(whole, max(int((seconds - whole) * 1e9), 1)))
        if _libc.timer_settime(self._timer, 0, ctypes.byref(spec), None) != 0:
            error = ctypes.get_errno()
            _libc.timer_delete(self._timer)
            raise OSError(error, 'timer_settime failed')
        self._armed = True

    def cancel(self) -> None:
        """Disarm the timer before it fires."""
        if self._armed:
            self._armed = False
            _libc.timer_delete(self._timer)
