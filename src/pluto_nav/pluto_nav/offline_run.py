"""A recording through Pluto's localization without ROS: what ``offline_nav`` runs.

The localModule's part is done as the localModule does it (:class:`.dead_reckoning.DeadReckoning`
over the odometry, and over an IMU's heading as the localModule takes the DMU's when the log has
an IMU with an orientation; the robot's pose interpolated at each scan's time, moved to the laser
by its mount, the increment's covariance by :func:`.odometry_model.laser_increment`), and the estimator's
part by the modules' own :class:`.estimation.ScanCycle` round the chosen method, so that a log
gives offline what the modules would give on the robot, as fast as one core allows and the same
every time.
"""

from __future__ import annotations

import dataclasses
import heapq
import math
import time
from collections.abc import Callable, Iterator

import numpy as np
from numpy.typing import NDArray

from .dead_reckoning import DeadReckoning
from .estimation import Method, Scan, ScanCycle
from .geometry import compose, inverse
from .logs import ImuRecord, OdometryRecord, RobotLog, ScanRecord
from .odometry_model import laser_increment

__all__ = ['OfflineResult', 'run_offline']


@dataclasses.dataclass
class OfflineResult:
    """:ivar stamps: the time of each scan used; ``laser`` and ``robot`` its poses (``(N, 3)``),
        the method's estimate at that scan (SLAM: replaced by the final trajectory, see
        :func:`run_offline`).
    :ivar odometry: the robot's dead-reckoned pose at each of those scans.
    :ivar matched: scans whose update matched something.
    :ivar skipped: scans not used (no odometry around their time, fatal values).
    :ivar seconds: processing time (wall clock).
    """

    stamps: NDArray
    laser: NDArray
    robot: NDArray
    odometry: NDArray
    matched: int
    skipped: int
    seconds: float


def run_offline(log: RobotLog, method: Method, *, start: tuple[float, float, float] | None = None,
                start_covariance: NDArray | None = None, imu: bool = True,
                progress: Callable[[int, int], None] | None = None) -> OfflineResult:
    """Every scan of ``log`` through ``method``.

    :param log: the recording (:func:`pluto_nav.logs.load_log`); it must have odometry.
    :param method: the estimator, a SLAM method or a localizer (:mod:`.slam_methods`,
        :mod:`.localizers`).
    :param start: the robot's pose at the first odometry record in the method's frame (a map's
        start place); None: the odometry's own first pose (a SLAM's map is then in the odometry
        frame, as comparable with it as can be).
    :param start_covariance: of the first laser pose the method starts from (None or zero: exact).
    :param imu: take the heading from the log's IMU orientation where it has one (as the
        localModule takes the DMU's); False: from the odometry alone.
    :param progress: called with (scans done, scans in all) now and then.
    :raises ValueError: the log has no odometry.
    """
    begun = time.perf_counter()
    if not log.odometry:
        raise ValueError(f'{log.path}: no odometry: neither odometry records nor odometry in the laser lines')
    first = log.odometry[0]
    dr = DeadReckoning(first.pose if start is None else start, clock=None)   # every sample at once, none late
    inputs = _inputs(log, imu)
    cycle = ScanCycle(method)
    covariance = np.zeros((3, 3)) if start_covariance is None else start_covariance
    stamps, laser, odometry, used = [], [], [], []
    matched = skipped = 0
    last: tuple[float, NDArray] | None = None
    total = len(log.scans)
    for count, scan in enumerate(log.scans, start=1):
        while (dr.latest is None or dr.latest.stamp < scan.stamp) and _feed(dr, inputs):
            pass
        robot = dr.at(scan.stamp)
        if robot is None:
            skipped += 1
            continue
        mount = np.asarray(scan.config.mount, dtype=np.float64)
        pose = compose(robot.pose, mount)
        increment_cov = None
        if last is not None:
            since = dr.increment_between(last[0], scan.stamp)
            if since is not None:
                increment_cov = laser_increment(*since, mount)[1]
        last = (scan.stamp, pose)
        result = cycle.step(_scan(scan), pose, increment_cov, start=(pose, covariance))
        if result is None:
            skipped += 1
            continue
        matched += int(result)
        stamps.append(scan.stamp)
        laser.append(method.pose)
        odometry.append(robot.pose)
        used.append(mount)
        if progress is not None and (count % 50 == 0 or count == total):
            progress(count, total)
    if progress is not None:
        progress(total, total)
    laser_poses = np.array(laser, dtype=np.float64).reshape(-1, 3)
    trajectory = getattr(method, 'trajectory', None)
    if callable(trajectory):              # a SLAM: every scan at its place in the final map
        final = trajectory()
        if len(final) == len(laser_poses):
            laser_poses = final
    robot_poses = np.array([compose(p, inverse(m)) for p, m in zip(laser_poses, used)]).reshape(-1, 3)
    return OfflineResult(np.array(stamps), laser_poses, robot_poses, np.array(odometry).reshape(-1, 3),
                         matched, skipped, time.perf_counter() - begun)


def _inputs(log: RobotLog, imu: bool) -> Iterator[OdometryRecord | ImuRecord]:
    """Odometry and (when ``imu``) IMU records with an orientation, merged in time order (an
    IMU sample first at equal stamps: it must cover the odometry sample's time)."""
    headings = [r for r in log.imu if r.orientation is not None] if imu else []
    return heapq.merge(headings, log.odometry, key=lambda r: (r.stamp, isinstance(r, OdometryRecord)))


def _feed(dr: DeadReckoning, inputs: Iterator[OdometryRecord | ImuRecord]) -> bool:
    """The next input into the dead reckoning; False when there is none."""
    record = next(inputs, None)
    if record is None:
        return False
    if isinstance(record, OdometryRecord):
        dr.add_odometry(record.stamp, record.x, record.y, record.theta)
    else:
        roll, pitch, yaw = _euler(record.orientation)  # type: ignore[arg-type]
        dr.add_dmu(record.stamp, yaw, pitch, roll)
    return True


def _euler(q: tuple[float, float, float, float]) -> tuple[float, float, float]:
    """Roll, pitch and yaw of a quaternion (x, y, z, w)."""
    x, y, z, w = q
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


def _scan(record: ScanRecord) -> Scan:
    """A record as the estimators take a scan: NaN (no reading) as -1 is not, so NaN stays NaN,
    which the methods skip like a reading beyond range."""
    return Scan(record.stamp, record.ranges, record.angles, record.config.max_range
                if math.isfinite(record.config.max_range) else math.inf)
