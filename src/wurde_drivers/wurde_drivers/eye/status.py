"""What the Eye's displays report back: frames shown, the display rate, clicks and keys.

The displays call :meth:`DisplayStatus.shown`, :meth:`~DisplayStatus.click` and
:meth:`~DisplayStatus.key` from any thread; the module reads a :meth:`~DisplayStatus.snapshot`
for ImageDisplay's data. No ROS here.
"""

from __future__ import annotations

import collections
import dataclasses
import threading
import time

__all__ = ['RATE_WINDOW_S', 'DisplayStatus', 'StatusSnapshot']

#: The display rate is the frames shown in the last this many seconds, per second.
RATE_WINDOW_S = 2.0


@dataclasses.dataclass(frozen=True)
class StatusSnapshot:
    """ImageDisplay's data members at one moment."""

    frames_shown: int = 0
    display_rate: float = 0.0
    click_count: int = 0
    click_x: int = 0
    click_y: int = 0
    key: int = 0


class DisplayStatus:
    """Counters shared by the displays (writers) and the module (reader)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._state = StatusSnapshot()
        self._shown_at: collections.deque[float] = collections.deque()
        self._last_index = 0
        self.version = 0            #: bumped on every change, so the module publishes on change

    def shown(self, index: int) -> bool:
        """Frame ``index`` reached the screen; a frame counts once (the page may fetch it often).
        Returns whether it was new."""
        with self._lock:
            if index <= self._last_index:
                return False
            self._last_index = index
            now = time.monotonic()
            self._shown_at.append(now)
            self._state = dataclasses.replace(self._state, frames_shown=self._state.frames_shown + 1)
            self.version += 1
            return True

    def click(self, x: int, y: int) -> None:
        """A mouse click at image pixel (x, y) (the display divides out its scale)."""
        with self._lock:
            self._state = dataclasses.replace(self._state, click_count=self._state.click_count + 1,
                                              click_x=int(x), click_y=int(y))
            self.version += 1

    def key(self, code: int) -> None:
        """A key press (X keysym number in the window, the DOM key code on the page)."""
        with self._lock:
            self._state = dataclasses.replace(self._state, key=int(code))
            self.version += 1

    def snapshot(self) -> StatusSnapshot:
        """The counters now, with the display rate over the last :data:`RATE_WINDOW_S`."""
        with self._lock:
            now = time.monotonic()
            while self._shown_at and self._shown_at[0] < now - RATE_WINDOW_S:
                self._shown_at.popleft()
            rate = len(self._shown_at) / RATE_WINDOW_S
            return dataclasses.replace(self._state, display_rate=rate)
