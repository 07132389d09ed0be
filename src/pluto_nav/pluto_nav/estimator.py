"""What Pluto's pose estimators (poseModule, Pluto 7.1; slamModule, 7.2) share: the thread, the
setter, the status stream and the scan-by-scan predict/update cycle against the localModule.

Per scan: the Laser_Dead-Reckoning (1) increment since the last scan and its covariance drive the
method's predict step, the scan taken at that time (scan and stream (1) are paired by their stamps,
the scan's centre time) drives its update (:class:`pluto_nav.estimation.ScanCycle`, which
``offline_nav`` runs on recordings too), and the laser pose goes to Post_Pose (2) with the
estimator's setter, stamped with the scan's time.  A scan of the laser's fatal-error values (-1,
Pluto 8.1) is not used: the method only predicts.

The thread (the estimation activity of the module's loop): when it starts it reads the pose from
Laser_Pose (4) and takes the setter; it does not start while another estimator holds the setter;
when it stops it gives the setter back (a Post_Pose write with cmdFlags 0).

Status (FVectorState ``<name>/status``, published on every change and once a second): element[0] 1
the thread runs, 0 stopped — a request writing
element[0] = 0 or 1 stops or starts it (the proxy's start/stop activity); element[1] = 2 written as
a request is the estimator's one command (find-wall, save the map); element[2], element[3]: scans
used, scans whose lines matched nothing.
"""

from __future__ import annotations

import collections
import time

import numpy as np

from wurde_core import CommsManager, Logger
from wurde_core.interfaces import FVectorState, LocalizationPose, RangeFinder

from .estimation import Method, Scan, ScanCycle
from .streams import LASER_DEAD_RECKONING, LASER_POSE, NOBODY, POST_POSE, STREAMS, LocPose, read_pose, write_pose

__all__ = ['Estimator']

LOOP_S = 0.02
#: Scans kept while their Laser_Dead-Reckoning pose has not arrived (and the other way round).
MAX_WAITING = 20
#: Two stamps are the same scan when they differ by less than this (s).
SAME_SCAN_S = 1e-4
#: Seconds between two publications of an unchanged status: data channels are volatile, and a
#: status (Pluto's CORBA status interface could be read at any time) must reach late consumers.
STATUS_PERIOD_S = 1.0

class Estimator:
    """One estimator module; subclasses say what the method is and what ``element[1] = 2`` does."""

    #: The setter this estimator writes with (Pluto 3: 1 pose, 2 slam).
    SETTER = 1
    #: Uncertainty added to Laser_Pose's own when the thread starts (m, m, rad).
    START_SIGMA = (0.3, 0.3, np.radians(8.0))

    def __init__(self, manager: CommsManager, logger: Logger, method: Method, *, status: str,
                 laser: str, start_running: bool) -> None:
        """Register the estimator's streams with ``manager`` and publish its first status.

        :param manager: the module's CommsManager.
        :param logger: where the thread's starts and stops are logged.
        :param method: the estimation method the scan cycle runs (:mod:`.estimation`).
        :param status: the status stream's name (``pose/status``, ``slam/status``).
        :param laser: the laser module's name (its RangeFinder stream).
        :param start_running: start the thread at once (a request on the status stream can later).
        """
        self.manager, self.logger = manager, logger
        self.cycle = ScanCycle(method)
        self.laser_dr = LocalizationPose(STREAMS[LASER_DEAD_RECKONING])
        self.laser_pose = LocalizationPose(STREAMS[LASER_POSE])
        self.post = LocalizationPose(STREAMS[POST_POSE])
        self.scan = RangeFinder(laser)
        for obj in (self.laser_dr, self.laser_pose, self.scan):
            obj.set_queue_mode(True)
        self.post.set_auto_timestamp(False)
        self.status = FVectorState(status)
        for obj in (self.laser_dr, self.laser_pose, self.post, self.scan):
            manager.register_consumer(obj)
        manager.register_supplier(self.status)
        self.angles: np.ndarray | None = None
        self.fan: tuple[float, float] | None = None     # first beam's angle, step (RangeFinder info)
        self.max_range = np.inf
        self.scans: collections.deque[tuple[float, np.ndarray]] = collections.deque()
        self.dr_poses: collections.deque[LocPose] = collections.deque()
        self.adjusted: collections.deque[LocPose] = collections.deque()
        self.want_running = start_running
        self.running = False
        self.setter: int | None = None
        self.element = [0, 0, 0, 0]
        self.data: list[float] = []
        self.status_sent = -float('inf')
        self.publish_status()

    # -- what subclasses say ---------------------------------------------------------------------
    def command(self) -> None:
        """``element[1] = 2`` was requested."""

    @property
    def method(self) -> Method:
        return self.cycle.method

    def on_scan(self, scan: Scan) -> None:
        """Every good scan, whether the thread runs or not (e.g. the find-wall).

        :param scan: the scan, in the laser's frame; a scan of fatal-error values is not passed.
        """

    def on_stop(self) -> None:
        """The thread is stopping: called while it still holds the setter, which is released after."""

    def start_covariance(self, adjusted: LocPose) -> np.ndarray:
        """The filter's initial covariance from the Laser_Pose it starts at.

        That pose's own, widened by :attr:`START_SIGMA` (the a-priori map's frame is not the dead
        reckoning's).

        :param adjusted: the Laser_Pose (4) at the first scan; a covariance that is not finite counts as zero.
        :returns: 3x3 over (x, y, theta).
        """
        own = adjusted.covariance if np.all(np.isfinite(adjusted.covariance)) else np.zeros((3, 3))
        return own + np.diag(np.square(self.START_SIGMA))

    # -- one loop --------------------------------------------------------------------------------
    def step(self) -> None:
        self._take_inputs()
        while self.status.get_next_request():
            element = list(self.status.requests.element.get_value())
            if len(element) > 0 and element[0] in (0, 1):
                self.want_running = bool(element[0])
            if len(element) > 1 and element[1] == 2:
                self.command()
        if self.want_running and not self.running:
            self._start()
        elif not self.want_running and self.running:
            self._stop()
        self._process_scans()
        if time.monotonic() - self.status_sent >= STATUS_PERIOD_S:
            self.publish_status()

    def _take_inputs(self) -> None:
        while self.scan.get_next_info():
            info = self.scan.info
            self.max_range = float(info.max_range.get_value()) or np.inf
            self.fan = (float(info.theta_offset.get_value()), float(info.theta_separation.get_value()))
            self.angles = None
        while self.scan.get_next_data():
            ranges = np.asarray(self.scan.data.ranges, dtype=float)
            if self.fan is None:
                continue              # no info yet: the beams' angles are unknown
            if self.angles is None or len(self.angles) != len(ranges):
                self.angles = self.fan[0] + self.fan[1] * np.arange(len(ranges))
            self.scans.append((self.scan.data.timestamp.get_seconds(), ranges))
        while self.laser_dr.get_next_data():
            self.dr_poses.append(read_pose(self.laser_dr.data))
        while self.laser_pose.get_next_data():
            self.adjusted.append(read_pose(self.laser_pose.data))
        while self.post.get_next_info():
            self.setter = int(self.post.info.cmd_flags.get_value())
        for queue in (self.scans, self.dr_poses, self.adjusted):
            while len(queue) > MAX_WAITING:
                queue.popleft()

    # -- the thread ------------------------------------------------------------------------------
    def _start(self) -> None:
        if self.setter is not None and self.setter > NOBODY and self.setter != self.SETTER:
            return                       # another estimator holds the setter: wait for it
        self.running = True
        self.cycle.restart()             # the next scan initialises the method from Laser_Pose
        self.element[0] = 1
        self.logger.notice(f'{self.manager.name}: thread started')
        self.publish_status()

    def _stop(self) -> None:
        self.on_stop()
        self.running = False
        self.element[0] = 0
        self.write_post(LocPose(setter=NOBODY))
        self.logger.notice(f'{self.manager.name}: thread stopped; setter released')
        self.publish_status()

    def write_post(self, value: LocPose) -> None:
        """Send ``value`` to Post_Pose as a request.

        :param value: the pose and its setter; ``LocPose(setter=NOBODY)`` releases the setter.
        """
        write_pose(self.post.requests, value)
        self.post.publish_request()

    def _process_scans(self) -> None:
        while self.scans and self.dr_poses:
            t_scan, t_dr = self.scans[0][0], self.dr_poses[0].stamp
            if t_scan < t_dr - SAME_SCAN_S:
                self.scans.popleft()
                continue
            if t_dr < t_scan - SAME_SCAN_S:
                self.dr_poses.popleft()
                continue
            stamp, ranges = self.scans.popleft()
            dr = self.dr_poses.popleft()
            while self.adjusted and self.adjusted[0].stamp < stamp - SAME_SCAN_S:
                self.adjusted.popleft()
            adjusted = None
            if self.adjusted and abs(self.adjusted[0].stamp - stamp) <= SAME_SCAN_S:
                adjusted = self.adjusted.popleft()
            self._scan(stamp, ranges, dr, adjusted)

    def _scan(self, stamp: float, ranges: np.ndarray, dr: LocPose, adjusted: LocPose | None) -> None:
        if self.angles is None:
            return
        scan = Scan(stamp, ranges, self.angles, self.max_range)
        if not scan.fatal:
            self.on_scan(scan)
        if not self.running:
            return
        start = None
        if not self.cycle.started:
            if adjusted is None:
                return                   # wait for a scan whose Laser_Pose arrived too
            start = (np.array(adjusted.xytheta), self.start_covariance(adjusted))
        matched = self.cycle.step(scan, dr.xytheta, dr.covariance, start=start)
        if matched is None:
            return                       # Pluto 8.1: no laser data; dead reckoning only
        self.element[2] += 1
        if not matched:
            self.element[3] += 1
        self.write_post(self.estimate(dr, stamp, self.SETTER))

    def estimate(self, dr: LocPose, stamp: float, setter: int) -> LocPose:
        """The method's laser pose as a Post_Pose value.

        :param dr: the Laser_Dead-Reckoning pose (1) at the scan: z, attitude, pan and tilt come from it.
        :param stamp: the scan's time, seconds.
        :param setter: the cmdFlags to write with (:attr:`SETTER`, or the saving setter).
        """
        pose = self.method.pose
        return LocPose(pose=(pose[0], pose[1], dr.pose[2], pose[2], dr.pose[4], dr.pose[5]), pan=dr.pan,
                       tilt=dr.tilt, covariance=np.asarray(self.method.covariance)[:3, :3], setter=setter,
                       stamp=stamp)

    def publish_status(self) -> None:
        self.status.data.element = list(self.element)
        self.status.data.data = list(self.data)
        self.status.publish_data()
        self.status_sent = time.monotonic()
