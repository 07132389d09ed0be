"""GpsProxy: Pluto's gpsmeter proxy (Pluto 8.4) — the GPS fix on an x, y grid in metres.

"[Do] use the proxy in gpsmeter to get data into a xy grid in meter units ... Important information
is in force[0]=number of satellites and force[3]=GPS quality. The number of satellites should be
> 5 and the quality should be 2 for sub-meter accuracy."  The GPS module ``N`` supplies the fix on
``N`` (latitude, longitude, x east and y north in m around the grid origin of its info) and
Pluto's layout on ``N/Pluto`` (position x, y; force satellites, HDOP, altitude, quality); the
proxy reads ``N``.  A good fix (:attr:`GpsProxy.good`): more satellites than 5 — or than the info's
minimum, when it says one — and a quality at least as accurate as 2 (DGPS): GGA qualities are codes,
ranked 1 < 3 < 2 < 5 < 4 (``wurde_drivers.gps.quality``, which this package may not import).
"""

from __future__ import annotations

import dataclasses

from wurde_core import CommsManager
from wurde_core.interfaces import GPS

from .proxy import Proxy

__all__ = ['Fix', 'GpsProxy']

#: The measured GGA qualities, least accurate first (as wurde_drivers.gps.quality).
ACCURACY_ORDER = (1, 3, 2, 5, 4)
#: Pluto 8.4's good fix: more than 5 satellites, quality 2 (or better).
MIN_SATELLITES, MIN_QUALITY = 5, 2


@dataclasses.dataclass(frozen=True)
class Fix:
    latitude: float
    longitude: float
    altitude: float
    x: float
    y: float
    satellites: int
    quality: int
    hdop: float
    stamp: float


class GpsProxy(Proxy):
    """The GPS ``name`` as seen from ``manager``: :attr:`fix`, :attr:`good`, :attr:`origin`."""

    def __init__(self, manager: CommsManager, name: str = 'PlutoGPS') -> None:
        """Read the GPS stream ``name``.

        :param manager: the program's manager.
        :param name: the gpsmeter module's name (its stream).
        """
        super().__init__(manager)
        self.gps = self._consume(GPS(name))
        self.fix: Fix | None = None
        #: The grid's origin (latitude, longitude), from the info (None before it).
        self.origin: tuple[float, float] | None = None
        self.min_satellites, self.min_quality = MIN_SATELLITES, MIN_QUALITY

    @property
    def xy(self) -> tuple[float, float] | None:
        """The fix on the grid: m east and north of the origin."""
        return (self.fix.x, self.fix.y) if self.fix is not None else None

    @property
    def good(self) -> bool:
        """Enough satellites and a quality at least as accurate as the minimum (see above)."""
        f = self.fix
        if f is None or f.quality not in ACCURACY_ORDER or f.satellites <= self.min_satellites:
            return False
        if self.min_quality not in ACCURACY_ORDER:
            return True
        return ACCURACY_ORDER.index(f.quality) >= ACCURACY_ORDER.index(self.min_quality)

    def _take(self) -> None:
        while self.gps.get_next_info():
            info = self.gps.info
            self.origin = (float(info.origin_latitude.get_value()), float(info.origin_longitude.get_value()))
            self.min_satellites = int(info.min_satellites.get_value()) or MIN_SATELLITES
            self.min_quality = int(info.min_quality.get_value())
        while self.gps.get_next_data():
            d = self.gps.data
            self.fix = Fix(d.latitude, d.longitude, d.altitude, d.x, d.y, int(d.satellites), int(d.quality),
                           d.hdop, d.timestamp.get_seconds())
