"""What a robot's recording holds, whatever file it came from: the records every log reader yields.

A CARMEN log (:mod:`.carmen`) and a rosbag2 bag (:mod:`.rosbag`) are read into the same few
records, so that ``offline_nav``, ``carmen_log`` and the benchmarks handle both the same way.
Units are metres, radians and seconds; poses ``(x, y, theta)`` follow REP-103 (x forward, angles
counter-clockwise).  ``stamp`` is when the reading was taken on the robot: a CARMEN line's IPC
``timestamp``, a ROS message's ``header.stamp``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

__all__ = ['ImuRecord', 'LaserConfig', 'LogRecord', 'OdometryRecord', 'ParamRecord', 'ScanRecord',
           'TruePoseRecord', 'Pose2D']

Pose2D = tuple[float, float, float]


@dataclasses.dataclass(frozen=True)
class LaserConfig:
    """The geometry of one laser: beam ``i`` points at ``start_angle + i * angular_resolution`` in
    the laser's frame; ``mount`` is the laser's pose on the robot (x, y, theta).

    :ivar max_range: m; a reading at or beyond it saw nothing.
    :ivar min_range: m; a reading at or below it is no reading either.
    """

    start_angle: float
    angular_resolution: float
    max_range: float
    min_range: float = 0.0
    mount: Pose2D = (0.0, 0.0, 0.0)

    def angles(self, count: int) -> NDArray[np.float64]:
        """The direction of each of ``count`` beams in the laser's frame.

        :param count: the number of beams.
        :returns: ``(count,)`` radians.
        """
        return self.start_angle + self.angular_resolution * np.arange(count, dtype=float)


@dataclasses.dataclass(frozen=True)
class OdometryRecord:
    """The base's odometry: its pose in the odometry frame and its velocities."""

    stamp: float
    x: float
    y: float
    theta: float
    tv: float = 0.0
    rv: float = 0.0
    acceleration: float = 0.0
    #: Where it came from, for messages: ``file:line`` or ``bag:topic``.
    origin: str = ''

    @property
    def pose(self) -> Pose2D:
        return (self.x, self.y, self.theta)


@dataclasses.dataclass(frozen=True)
class ScanRecord:
    """One laser scan.

    :ivar ranges: m, one per beam, in beam order; a beam that saw nothing within range is ``inf``
        (readers turn ``>= max_range`` and ``+inf`` into ``inf``), a beam with no reading is NaN
        (an erroneous or missing reading, ``< min_range``, ``-inf``; REP-117): inf clears the way
        it looked along, NaN says nothing.
    :ivar config: the laser's geometry.
    :ivar channel: which laser of the robot: ``front`` or ``rear`` (CARMEN's FLASER/RLASER,
        ROBOTLASER1/2), ``raw1`` .. ``raw4`` (RAWLASERn), or a bag's topic name.
    :ivar odometry: the robot's odometry pose at the scan as the record itself carries it (CARMEN's
        odom fields), or None (a bag's scans carry none).
    :ivar laser_pose: the laser's pose as the record carries it (CARMEN's laser x, y, theta), or None.
    :ivar remissions: the remission (intensity) of each beam when the record has them, else None.
    """

    stamp: float
    ranges: NDArray[np.float64]
    config: LaserConfig
    channel: str = 'front'
    odometry: Pose2D | None = None
    laser_pose: Pose2D | None = None
    remissions: NDArray[np.float64] | None = None
    origin: str = ''

    @property
    def angles(self) -> NDArray[np.float64]:
        return self.config.angles(len(self.ranges))


@dataclasses.dataclass(frozen=True)
class TruePoseRecord:
    """CARMEN's TRUEPOS (a simulator's truth): the true pose and the odometry pose beside it."""

    stamp: float
    true_pose: Pose2D
    odometry: Pose2D
    origin: str = ''


@dataclasses.dataclass(frozen=True)
class ImuRecord:
    """An inertial reading: orientation as a quaternion (x, y, z, w; None when the sensor gives
    none), angular velocity (rad/s) and linear acceleration (m/s^2), both (x, y, z)."""

    stamp: float
    orientation: tuple[float, float, float, float] | None
    angular_velocity: tuple[float, float, float]
    linear_acceleration: tuple[float, float, float]
    origin: str = ''

    @property
    def yaw(self) -> float | None:
        if self.orientation is None:
            return None
        x, y, z, w = self.orientation
        return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


@dataclasses.dataclass(frozen=True)
class ParamRecord:
    """CARMEN's PARAM line: a parameter's name (``module_variable``) and its value as text."""

    stamp: float
    name: str
    value: str
    origin: str = ''


LogRecord = OdometryRecord | ScanRecord | TruePoseRecord | ImuRecord | ParamRecord
