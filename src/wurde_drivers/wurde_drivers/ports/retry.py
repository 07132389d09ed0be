"""When a driver tries again to open a device that is absent: at once the first time, then at
most every ``every_s`` seconds, so that the module's loop keeps running (and beating) while the
device is gone.  The one home of that timing for the serial link, the joystick and the cameras."""

from __future__ import annotations

import math

__all__ = ['RetryGate']


class RetryGate:
    """Ask :meth:`due` before each attempt to open; it says yes at most every ``every_s`` s."""

    def __init__(self, every_s: float) -> None:
        self.every_s = every_s
        self._next = -math.inf

    def due(self, now: float) -> bool:
        """Whether to try now; a yes starts the next wait."""
        if now < self._next:
            return False
        self._next = now + self.every_s
        return True

    def at_once(self) -> None:
        """The next :meth:`due` says yes (a device that comes straight back, a new path)."""
        self._next = -math.inf

    def later(self, now: float) -> None:
        """The next :meth:`due` says yes ``every_s`` after ``now`` (a device that just vanished)."""
        self._next = now + self.every_s

    def wait_s(self, now: float) -> float:
        """Seconds until :meth:`due` says yes."""
        return max(0.0, self._next - now)
