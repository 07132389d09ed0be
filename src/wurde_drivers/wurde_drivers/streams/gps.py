"""The stream of a GPS module, shared by the NMEA driver and the dummy GPS (Pluto 8.4).

A GPS module named ``N`` supplies one GPS stream ``N``: latitude, longitude, altitude, satellites,
fix quality, HDOP, the UTC time of the fix, and x (east), y (north) in metres in a local frame
around the origin given in the info — Pluto's gpsmeter grid. The info also says what counts as a
good fix (Pluto: more than 5 satellites and quality 2 for sub-metre accuracy). Each fix also goes
out as ``sensor_msgs/NavSatFix`` on ``/N/fix`` (:mod:`wurde_drivers.ros_std`).
"""

from __future__ import annotations

from wurde_core import CommsManager, Time
from wurde_core.interfaces import GPS

from ..ros_std import FixPublisher

__all__ = ['GpsStreams']


class GpsStreams:
    """The GPS supplier; :meth:`publish_info` once the origin is known, then :meth:`publish_fix`."""

    def __init__(self, name: str) -> None:
        self._name = name
        self.gps = GPS(name)
        self.gps.set_auto_timestamp(False)
        self.fixes = 0
        self._fix: FixPublisher | None = None

    def register(self, manager: CommsManager) -> None:
        manager.register_supplier(self.gps)
        if '/' not in self._name:
            self._fix = FixPublisher(manager.node, self._name)

    def publish_info(self, *, latitude: float, longitude: float, min_satellites: int = 6,
                     min_quality: int = 2) -> None:
        info = self.gps.info
        info.origin_latitude.set_value(latitude)
        info.origin_longitude.set_value(longitude)
        info.min_satellites.set_value(min_satellites)
        info.min_quality.set_value(min_quality)
        self.gps.publish_info()

    def publish_fix(self, *, latitude: float, longitude: float, altitude: float, satellites: int,
                    quality: int, hdop: float, fix_time: float, x: float, y: float, stamp: float) -> None:
        d = self.gps.data
        d.latitude, d.longitude, d.altitude = latitude, longitude, altitude
        d.satellites, d.quality, d.hdop = int(satellites), int(quality), float(hdop)
        d.fix_time, d.x, d.y = fix_time, x, y
        d.timestamp = Time(stamp)
        self.gps.publish_data()
        if self._fix is not None:
            self._fix.publish(latitude=latitude, longitude=longitude, altitude=altitude, quality=quality,
                              stamp=stamp)
        self.fixes += 1
