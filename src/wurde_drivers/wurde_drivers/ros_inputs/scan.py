"""A ``sensor_msgs/LaserScan`` as the suite's laser streams carry it (pure numpy, no rclpy).

The suite's ranges (:mod:`wurde_drivers.streams.laser`, Pluto 8.1) are metres in the robot's
counter-clockwise order; ``inf`` is a beam that saw nothing within range, NaN a beam with no
reading, and −1 (every beam) only the SICK's fatal error — never a normal scan's value.  Every
consumer takes a beam as an echo only when it is finite and positive (the avoidModule, the
motionModule), and the line extraction also below the info's ``max_range`` (poseModule,
slamModule).  A LaserScan (REP-117) becomes:

=================================== ======================================================
LaserScan value                     suite value
=================================== ======================================================
``range_min <= r < range_max``      ``r``
``r >= range_max``, ``+inf``        ``inf`` (nothing within range)
NaN, ``r < range_min``, ``-inf``    NaN (no reading; REP-117's −inf, "too close", too)
=================================== ======================================================

The beams are put in the robot's order: reversed when the laser's angles run clockwise on the
robot (a negative ``angle_increment``, or a laser mounted upside down, but not both).  The fan's
first bearing is in the robot's frame (the mount's yaw included), its step positive.  The stamp
is the scan's centre: the header's stamp (the first beam) plus ``(n - 1) / 2`` times the time
between beams, and its end (the last beam) is ``(n - 1)`` of them on.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .frames import Mount

__all__ = ['RobotScan', 'suite_ranges', 'to_robot']


@dataclasses.dataclass(frozen=True)
class RobotScan:
    """One scan as the laser streams publish it."""

    ranges: NDArray       # metres, robot order (counter-clockwise)
    first: float          # bearing of ranges[0], robot frame (rad, in [-pi, pi])
    step: float           # rad between two beams, > 0
    max_range: float      # the scan's range_max (m; inf when the driver gives none)
    centre: float         # stamp of the scan's centre (s)
    end: float            # stamp of its last beam (s)


def suite_ranges(ranges: ArrayLike, *, range_min: float, range_max: float) -> NDArray:
    """The ranges with the suite's ``inf`` and NaN (table above), in the laser's order.

    A ``range_max`` that is not positive and finite, or a ``range_min`` that is not finite and
    non-negative, is a driver's omission: only ``inf`` is nothing within range then, and only
    negative values are no reading.
    """
    r = np.array(ranges, dtype=np.float64)
    low = range_min if math.isfinite(range_min) and range_min >= 0.0 else 0.0
    high = range_max if math.isfinite(range_max) and range_max > 0.0 else math.inf
    with np.errstate(invalid='ignore'):
        far = r >= high
        short = (r < low) | np.isneginf(r)
    r[far] = math.inf
    r[short] = math.nan
    return r


def to_robot(ranges: Sequence[float] | NDArray, *, angle_min: float, angle_increment: float,
             range_min: float, range_max: float, stamp: float, time_increment: float,
             mount: Mount) -> RobotScan:
    """The scan in the robot's order and frame.

    :raises ValueError: fewer than 2 beams, or angles that are not finite or do not advance.
    """
    count = len(ranges)
    if count < 2:
        raise ValueError(f'{count} beams: a scan needs 2 or more')
    if not (math.isfinite(angle_min) and math.isfinite(angle_increment) and angle_increment != 0.0):
        raise ValueError(f'angle_min {angle_min} and angle_increment {angle_increment}: the beams '
                         'have no direction')
    values = suite_ranges(ranges, range_min=range_min, range_max=range_max)
    last = angle_min + (count - 1) * angle_increment
    clockwise = (angle_increment < 0.0) != mount.upside_down
    if clockwise:
        values = values[::-1].copy()
        first = mount.bearing(last)
    else:
        first = mount.bearing(angle_min)
    between = abs(time_increment) if math.isfinite(time_increment) else 0.0
    max_range = range_max if math.isfinite(range_max) and range_max > 0.0 else math.inf
    return RobotScan(values, math.remainder(first, math.tau), abs(angle_increment), max_range,
                     stamp + (count - 1) / 2 * between, stamp + (count - 1) * between)
