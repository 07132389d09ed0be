"""SickProxy: Pluto's sick proxy (Pluto 8.1) — the laser's three interfaces.

The laser module ``N`` supplies every beam stamped at the scan's centre on ``N`` (Pluto's second
interface), the 181-beam RWI copy stamped at arrival on ``N/RWI`` (the first) and the timing on
``N/Timing`` (the third: the number of scan points).  "All data is set to -1 if a fatal error
occurs"; "the Corba interface does not allow one to change any settings on the sick scanner" — the
proxy has accessors only.
"""

from __future__ import annotations

import dataclasses
import math

from wurde_core import CommsManager
from wurde_core.interfaces import FVectorState, RangeFinder

from .proxy import Proxy

__all__ = ['Scan', 'SickProxy']


@dataclasses.dataclass(frozen=True)
class Scan:
    """One scan: ranges in m (inf: nothing seen), counter-clockwise from ``first`` by ``step`` rad."""

    ranges: tuple[float, ...]
    first: float
    step: float
    stamp: float

    @property
    def fatal(self) -> bool:
        """Pluto 8.1's fatal error: every range -1 while the scanner reboots."""
        return bool(self.ranges) and all(r == -1.0 for r in self.ranges)

    def bearing(self, index: int) -> float:
        """The bearing of beam ``index`` (rad, counter-clockwise, 0 straight ahead).

        :param index: the beam's index in :attr:`ranges`.
        """
        return self.first + index * self.step

    def ahead(self) -> float:
        """The range of the beam nearest straight ahead."""
        index = min(range(len(self.ranges)), key=lambda i: abs(self.bearing(i)))
        return self.ranges[index]

    def nearest(self) -> tuple[float, float]:
        """(range, bearing) of the nearest thing seen."""
        index = min(range(len(self.ranges)), key=lambda i: self.ranges[i] if self.ranges[i] >= 0 else math.inf)
        return self.ranges[index], self.bearing(index)


class SickProxy(Proxy):
    """The laser ``name`` as seen from ``manager``: :attr:`scan`, :attr:`rwi`, :attr:`points`."""

    def __init__(self, manager: CommsManager, name: str = 'PlutoLaser') -> None:
        """Read the laser's streams ``<name>``, ``<name>/RWI`` and ``<name>/Timing``.

        :param manager: the program's manager.
        :param name: the laser module's name.
        """
        super().__init__(manager)
        self.main = self._consume(RangeFinder(name))
        self.rwi_stream = self._consume(RangeFinder(f'{name}/RWI'))
        self.timing = self._consume(FVectorState(f'{name}/Timing'))
        self.scan: Scan | None = None
        self.rwi: Scan | None = None
        #: The timing interface's number of scan points (None before the first).
        self.points: int | None = None
        #: Scans taken in so far.
        self.scans = 0
        self._fans: dict[int, tuple[float, float]] = {}

    def _fan(self, obj: RangeFinder, count: int) -> tuple[float, float]:
        info = obj.info
        step = float(info.theta_separation.get_value())
        if step == 0.0 and count > 1:
            step = math.pi / (count - 1)              # a SICK's 180 degrees
            return -math.pi / 2, step
        return float(info.theta_offset.get_value()), step

    def _take(self) -> None:
        for obj in (self.main, self.rwi_stream):
            obj.get_next_info()
            while obj.get_next_data():
                ranges = tuple(float(r) for r in obj.data.ranges)
                scan = Scan(ranges, *self._fan(obj, len(ranges)), obj.data.timestamp.get_seconds())
                if obj is self.main:
                    self.scan, self.scans = scan, self.scans + 1
                else:
                    self.rwi = scan
        while self.timing.get_next_data():
            element = list(self.timing.data.element)
            self.points = int(element[0]) if element else None
