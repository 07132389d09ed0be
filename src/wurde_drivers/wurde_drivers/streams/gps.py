"""The stream of a GPS module, shared by the NMEA driver and the dummy GPS (Pluto 8.4).

A GPS module named ``N`` supplies one GPS stream ``N``: latitude, longitude, altitude, satellites,
fix quality, HDOP, the UTC time of the fix, and x (east), y (north) in metres in a local frame
around the origin given in the info — Pluto's gpsmeter grid.  The info also says what counts as a
good fix (Pluto: more than 5 satellites and quality 2); the quality is a GGA code ranked by
accuracy, not a number to compare with ``>=`` (:mod:`wurde_drivers.gps.quality`).  Each fix also
goes out as ``sensor_msgs/NavSatFix`` on ``/N/fix`` (:mod:`wurde_drivers.ros_std`) in frame ``N``.

Pluto's own layout (Pluto 8.4: "force[0]=number of satellites and force[3]=GPS quality") is the
extra ActuatorState stream ``N/Pluto`` (:data:`PLUTO_SUFFIX`), one event per fix with the same
time stamp; docs/wurde-drivers.md ("streams.gps") gives its fields.  Latitude and longitude are
not in it (a Float cannot hold them to the metre).
"""

from __future__ import annotations

from wurde_core import CommsManager, Time
from wurde_core.interfaces import GPS, ActuatorState

from ..mounting import Mounting
from ..ros_std import FixPublisher
from ..ros_std_frames import StaticFrames, frame_of

__all__ = ['PLUTO_SUFFIX', 'GpsStreams', 'pluto_force']

#: The Pluto-layout stream of a GPS module ``N`` is ``N`` + this.
PLUTO_SUFFIX = '/Pluto'


def pluto_force(*, satellites: int, hdop: float, altitude: float, quality: int) -> list[float]:
    """The ``force`` vector of the Pluto layout: force[0] satellites, force[3] quality."""
    return [float(satellites), float(hdop), float(altitude), float(quality)]


class GpsStreams:
    """The GPS supplier; :meth:`publish_info` once the origin is known, then :meth:`publish_fix`."""

    def __init__(self, name: str, *, mount: Mounting) -> None:
        """:param mount: where the antenna sits (translation only)."""
        self._name = name
        self.mount = Mounting(mount.x, mount.y, mount.z)
        self.gps = GPS(name)
        self.gps.set_auto_timestamp(False)
        #: The same fixes in Pluto 8.4's layout (see the module's table).
        self.pluto = ActuatorState(name + PLUTO_SUFFIX)
        self.pluto.set_auto_timestamp(False)
        self.fixes = 0
        self._fix: FixPublisher | None = None

    def register(self, manager: CommsManager) -> None:
        manager.register_supplier(self.gps)
        manager.register_supplier(self.pluto)
        if '/' not in self._name:
            self._fix = FixPublisher(manager.node, self._name)
        StaticFrames(manager.node).set([(frame_of(self._name), self.mount)])

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
        p = self.pluto.data
        p.cmd_flags = 0
        p.position = [float(x), float(y)]
        p.velocity = []
        p.force = pluto_force(satellites=satellites, hdop=hdop, altitude=altitude, quality=quality)
        p.acceleration = []
        p.timestamp = Time(stamp)
        self.pluto.publish_data()
        if self._fix is not None:
            self._fix.publish(latitude=latitude, longitude=longitude, altitude=altitude, quality=quality,
                              hdop=hdop, stamp=stamp)
        self.fixes += 1
