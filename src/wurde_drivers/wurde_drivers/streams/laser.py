"""The streams of a laser module, shared by the SICK driver, the dummy SICK and ros_inputs.

Pluto's sickModule has three interfaces (8.1), and WURDE's SICKServer one RangeFinder named after
the laser (7.5). A laser module named ``N`` supplies ``N`` (RangeFinder, every beam, stamped at
the scan's centre: WURDE's stream), ``N/RWI`` (RangeFinder, 181 beams stamped when the data
arrived, as the old RWI interface) and ``N/Timing`` (FVectorState, the number of scan points),
and a ``sensor_msgs/LaserScan`` of ``N`` on ``/N/scan`` (:mod:`wurde_drivers.ros_std`).

Ranges are metres in the robot's order (counter-clockwise from −90° to +90°, also for a laser
mounted upside down); a beam that saw nothing within range reads ``inf``.  When the laser has a
fatal error every range is −1 until it is back (Pluto 8.1: "all data is set to -1").

Any other fan (a ROS robot's laser through ``ros_inputs``) is announced with a :class:`Fan`,
which changes what ``N/RWI`` and ``/N/scan`` carry; see docs/wurde-drivers.md ("streams.laser").
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable

from wurde_core import CommsManager, Time
from wurde_core.interfaces import FVectorState, RangeFinder

from ..mounting import Mounting
from ..ros_std import ScanPublisher
from ..ros_std_frames import StaticFrames, frame_of
from ..sick import facts

__all__ = ['Fan', 'LaserStreams']


@dataclasses.dataclass(frozen=True)
class Fan:
    """A uniform fan of beams in the robot's frame, in the suite's counter-clockwise order.

    :param first: bearing of the first beam (rad, robot frame: 0 ahead, counter-clockwise).
    :param step: angle between two beams (rad, > 0).
    :param time_increment: seconds between two measurements (0: unknown), for ``/N/scan``.
    """

    first: float
    step: float
    time_increment: float = 0.0

    def __post_init__(self) -> None:
        if not (math.isfinite(self.first) and math.isfinite(self.step) and self.step > 0):
            raise ValueError(f'a fan needs a finite first bearing and a positive step, not {self}')


class LaserStreams:
    """Suppliers of one laser; :meth:`register`, :meth:`publish_info`, then :meth:`publish_scan`."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.scan = RangeFinder(name)
        self.rwi = RangeFinder(f'{name}/RWI')
        self.timing = FVectorState(f'{name}/Timing')
        for obj in (self.scan, self.rwi, self.timing):
            obj.set_auto_timestamp(False)
        self.count = 0
        self.max_range = 0.0
        self.scan_time = 0.0
        self.scans = 0
        #: The fan announced last (None: the SICK's 180°).
        self.fan: Fan | None = None
        self._node: object = None
        self._ros: ScanPublisher | None = None
        self._frames: StaticFrames | None = None

    def register(self, manager: CommsManager) -> None:
        for obj in (self.scan, self.rwi, self.timing):
            manager.register_supplier(obj)
        self._node = manager.node
        self._frames = StaticFrames(manager.node)

    def publish_info(self, *, count: int, max_range: float, mount_x: float = 0.0, mount_y: float = 0.0,
                     mount_z: float = 0.4, scan_time: float = 0.0, fan: Fan | None = None) -> None:
        """The RangeFinder info: a uniform fan over 180° (the SICK's), or ``fan``, at the laser's
        mounting point; again whenever the mounting or the fan changes.

        ``scan_time`` (s between scans) goes into the standard LaserScan on ``/<name>/scan``.
        """
        self.count, self.max_range, self.scan_time = count, max_range, scan_time
        self.fan = fan
        if self._node is not None and '/' not in self.name:
            if fan is None and self._ros is None:
                self._ros = ScanPublisher(self._node, self.name, max_range=max_range,
                                          time_increment=1.0 / facts.MIRROR_HZ / 360.0)  # a turn per 360°
            elif fan is not None:
                if self._ros is None:
                    self._ros = ScanPublisher(self._node, self.name, max_range=max_range)
                self._ros.max_range, self._ros.time_increment = max_range, fan.time_increment
                self._ros.angle_min, self._ros.angle_increment = fan.first, fan.step
        if self._frames is not None:
            self._frames.set([(frame_of(self.name), Mounting(mount_x, mount_y, mount_z))])
        rwi_beams = facts.RWI_VALUES if fan is None else count
        for obj, beams in ((self.scan, count), (self.rwi, rwi_beams)):
            first, step = (-math.pi / 2, math.pi / (beams - 1)) if fan is None else (fan.first, fan.step)
            info = obj.info
            info.max_range.set_value(max_range)
            info.uniform.set_value(True)
            info.half_angle.set_value(step / 2)
            info.x_offset.set_value(mount_x)
            info.y_offset.set_value(mount_y)
            info.z_offset.set_value(mount_z)
            info.theta_offset.set_value(first)
            info.theta_separation.set_value(step)
            obj.publish_info()

    def publish_scan(self, ranges: Iterable[float], *, centre_stamp: float, arrival_stamp: float) -> None:
        """One scan in robot order; the RWI stream gets every other beam of a SICK's 361-beam
        scan (a :class:`Fan`'s: every beam)."""
        values = [float(r) for r in ranges]
        self.scan.data.ranges = values
        self.scan.data.timestamp = Time(centre_stamp)
        self.scan.publish_data()
        sick_half = self.fan is None and len(values) == facts.VALUES_AT[0.5]
        self.rwi.data.ranges = values[::2] if sick_half else values
        self.rwi.data.timestamp = Time(arrival_stamp)
        self.rwi.publish_data()
        self.timing.data.element = [len(values)]
        self.timing.data.data = []
        self.timing.data.timestamp = Time(centre_stamp)
        self.timing.publish_data()
        if self._ros is not None and values and values[0] != -1.0:
            self._ros.publish(values, centre_stamp, self.scan_time)
        self.scans += 1

    def publish_fatal(self, stamp: float) -> None:
        """Pluto 8.1: during a fatal error (the sensor reboots) every range is −1."""
        count = self.count or facts.VALUES_AT[0.5]
        self.publish_scan([-1.0] * count, centre_stamp=stamp, arrival_stamp=stamp)
