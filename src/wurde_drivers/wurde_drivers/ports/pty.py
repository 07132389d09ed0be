"""A device on the far end of a pseudo-terminal, for emulators of serial devices.

The emulator owns the master side; the driver opens the slave path (``device.path``) with pyserial
exactly as it would open ``/dev/ttyS0``. Baud-rate changes the driver makes on the slave are visible
on the master (docs/protocols.md 6), so an emulator can follow a device's baud switching through
:attr:`PtyEmulator.baudrate`. The slave fd is kept open here: reads on a master fail with EIO once no
slave fd is open, which would make the emulator die whenever the driver reconnects.

Subclasses implement :meth:`on_bytes` (called from the reader thread with whatever arrived) and may
override :meth:`tick` (called about every ``tick_s`` seconds, for streaming devices). Both run on the
one emulator thread, so a subclass needs no locks of its own for its protocol state.
"""

from __future__ import annotations

import os
import select
import termios
import threading
import time
import tty

#: termios speed constants back to numbers (the ones a driver here may set).
_SPEEDS = {getattr(termios, f'B{rate}'): rate for rate in
           (1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 921600)
           if hasattr(termios, f'B{rate}')}


class PtyEmulator:
    """Base of the serial emulators: a pty pair, one thread, ``on_bytes`` and ``tick`` hooks.

    Use as a context manager, or call :meth:`start` and :meth:`stop` (idempotent).
    """

    def __init__(self, *, tick_s: float = 0.005) -> None:
        """Open the pty pair (raw, the master non-blocking); :meth:`start` runs the thread.

        :param tick_s: seconds between two turns of the thread: the longest wait for input, and the
            period of :meth:`tick`.
        """
        self._master, self._slave = os.openpty()
        tty.setraw(self._master)
        tty.setraw(self._slave)
        # Nobody reading the slave must not block the emulator: a real line drops bytes then.
        os.set_blocking(self._master, False)
        self.path = os.ttyname(self._slave)
        self.tick_s = tick_s
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=type(self).__name__, daemon=True)
        self._write_lock = threading.Lock()
        #: Set while the emulator pretends to be unplugged: nothing is read or written.
        self.unplugged = threading.Event()
        self.bytes_in = 0
        self.bytes_out = 0
        #: Bytes lost because the driver's side was full (nobody reading).
        self.bytes_dropped = 0
        self.error: BaseException | None = None
        #: Turns of the emulator's thread completed (see :meth:`settle`).
        self.turns = 0
        self._turned = threading.Condition()

    # -- life cycle ---------------------------------------------------------------------------
    def start(self) -> 'PtyEmulator':
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        if self._thread.is_alive() and threading.current_thread() is not self._thread:
            self._thread.join(timeout=5.0)
        for fd in (self._master, self._slave):
            try:
                os.close(fd)
            except OSError:
                pass
        self._master = self._slave = -1

    def __enter__(self) -> 'PtyEmulator':
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- line state ---------------------------------------------------------------------------
    @property
    def baudrate(self) -> int:
        """The speed the driver last set on the line (0 if it is not a standard one)."""
        try:
            speed = termios.tcgetattr(self._master)[4]
        except termios.error:
            return 0
        return _SPEEDS.get(speed, 0)

    def write(self, data: bytes) -> None:
        """Send ``data`` to the driver (dropped while unplugged).

        :param data: the bytes; what the driver's side cannot take now is dropped and counted in
            ``bytes_dropped``, as on a real line.
        """
        if self.unplugged.is_set() or self._master < 0:
            return
        with self._write_lock:
            view = memoryview(data)
            while view:
                try:
                    written = os.write(self._master, view)
                except (BlockingIOError, OSError):
                    self.bytes_dropped += len(view)
                    return
                view = view[written:]
                self.bytes_out += written

    def settle(self, timeout: float = 10.0) -> bool:
        """Wait until the emulator's thread has finished two turns since this call.

        After a change made from another thread (``silent``, ``unplugged``, a fault), whatever
        the turn under way had decided under the old state is then on the line, and nothing
        more of it is to come: the event tests wait for instead of a guessed time.

        :param timeout: the longest wait in seconds.
        :returns: False if the thread did not turn within ``timeout`` (it is stopped, or stuck).
        """
        with self._turned:
            target = self.turns + 2
            self._turned.wait_for(
                lambda: self.turns >= target or not self._thread.is_alive(), timeout)
            return self.turns >= target

    # -- hooks ----------------------------------------------------------------------------------
    def on_bytes(self, data: bytes) -> None:
        """Handle bytes the driver wrote (override); called on the emulator's thread.

        :param data: what one read of the master returned (up to 4096 bytes).
        """

    def tick(self, now: float) -> None:
        """Periodic work, e.g. a streaming device's next telegram (override); called on the emulator's thread.

        :param now: ``time.monotonic()`` of this turn.
        """

    # -- thread ---------------------------------------------------------------------------------
    def _run(self) -> None:
        try:
            while not self._stop.is_set():
                ready, _, _ = select.select([self._master], [], [], self.tick_s)
                if ready:
                    try:
                        data = os.read(self._master, 4096)
                    except (BlockingIOError, OSError):
                        data = b''
                    if data and not self.unplugged.is_set():
                        self.bytes_in += len(data)
                        self.on_bytes(data)
                if not self.unplugged.is_set():
                    self.tick(time.monotonic())
                with self._turned:
                    self.turns += 1
                    self._turned.notify_all()
        except BaseException as error:  # kept for the test to see; the thread must not die silently
            self.error = error
            raise


PtyDevice = PtyEmulator  # old name (docs/naming.md)
