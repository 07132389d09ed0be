"""SlamProxy: the slamModule's proxy (Pluto 7.2) — start and stop its thread, save its map.

``slam/status`` (FVectorState): element[0] 1 the thread runs, 0 stopped (a request writing 0 or 1
stops or starts it; stopping saves the map: "When the slam thread is stopped the map is saved so
one should wait"); "Set element[1]=2 to save the map. The slamModule then sets element[1]=-1 while
it saves the map ... When the map has been saved element[1] is set 0"; element[2..3] scans used
and unmatched; data = [confirmed walls, landmarks, maps saved].
"""

from __future__ import annotations

from wurde_core import CommsManager
from wurde_core.interfaces import FVectorState

from .proxy import Proxy

__all__ = ['SlamProxy']

STATUS = 'slam/status'


class SlamProxy(Proxy):
    """The slamModule as seen from ``manager``."""

    def __init__(self, manager: CommsManager) -> None:
        """Read and request on the slamModule's status stream, every status kept.

        :param manager: the program's manager.
        """
        super().__init__(manager)
        self.status = self._consume(FVectorState(STATUS), queue_mode=True)   # the save's -1 too
        self.element: list[int] = []
        self.data: list[float] = []

    def _write(self, element: list[int]) -> bool:
        self.status.requests.element.set_value(element)
        return self._request(self.status)

    def start_activity(self) -> bool:
        """Start the slam thread (a new map, in the frame of the Laser_Pose it starts at)."""
        return self._write([1])

    def stop(self) -> bool:
        """Stop the thread; it saves the map first."""
        return self._write([0])

    def save_map(self) -> bool:
        """Save the map now (element[1] = 2); the cycle goes on."""
        return self._write([-1, 2])      # element[0] neither 0 nor 1: the thread as it is

    def _take(self) -> None:
        while self.status.get_next_data():
            self.element = list(self.status.data.element)
            self.data = list(self.status.data.data)

    @property
    def running(self) -> int | None:
        """element[0]: 1 running, 0 stopped (None before the first status)."""
        return self.element[0] if self.element else None

    @property
    def saving(self) -> bool:
        return len(self.element) > 1 and self.element[1] == -1

    @property
    def maps_saved(self) -> int:
        return int(self.data[2]) if len(self.data) > 2 else 0

    @property
    def walls(self) -> int:
        return int(self.data[0]) if self.data else 0

    @property
    def landmarks(self) -> int:
        return int(self.data[1]) if len(self.data) > 1 else 0
