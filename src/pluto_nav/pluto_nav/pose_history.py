"""Where the robot was at a moment of the recent past: odometry poses by their stamps.

A scan is older than the odometry by the time it takes to reach the computer: the SICK at 38400
baud stamps a scan with its centre time, about 0.2 s before its last byte arrives
(:mod:`wurde_drivers.sick`).  A robot turning at 1 rad/s has turned 0.2 rad meanwhile, and a
module that puts the scan at the robot's latest pose sees a box 1 m ahead 0.2 m beside where it
is.  :meth:`PoseHistory.at` gives the pose at the scan's stamp, on the clock the base stamps its
odometry with (the SICK driver and the base driver both stamp with the robot computer's clock;
the simulator's laser with the base's own).
"""

from __future__ import annotations

import bisect
import collections
import math

from .geometry import interpolate

__all__ = ['TRUTH_GAP_S', 'PoseHistory']

#: For checks that pair an estimate with the simulator's truth (``max_gap_s``): the truth comes
#: every simulation step (0.02 s), so two samples further apart than this (s) were lost (a
#: restarted base not yet matched) and the time between them is not known.
TRUTH_GAP_S = 0.5

Pose2 = tuple[float, float, float]


class PoseHistory:
    """Stamped poses of the last ``keep_s`` seconds (by stamp), interpolated between samples.

    :param keep_s: how far back poses are kept (s of the stamps' clock).
    :param ahead_s: a stamp up to this much after the latest sample is given the latest pose
        (odometry comes at 10 Hz: a scan may be newer than the last sample); later is not known.
    :param max_gap_s: two samples further apart than this do not cover the time between them
        (samples lost: a stamp there is not known).  A check that pairs an estimate with the
        truth needs it: a restarted base's truth reached the soak 2.6 s after its first samples
        had moved the robot 0.18 m, and the truth drawn straight across the gap put a right
        Pose 0.14 m and 12 degrees off.
    """

    def __init__(self, keep_s: float = 2.0, ahead_s: float = 0.2, max_gap_s: float = math.inf) -> None:
        self.keep_s, self.ahead_s, self.max_gap_s = keep_s, ahead_s, max_gap_s
        self._stamps: collections.deque[float] = collections.deque()
        self._poses: collections.deque[Pose2] = collections.deque()

    def __len__(self) -> int:
        return len(self._stamps)

    @property
    def latest(self) -> float:
        """The latest stamp (-inf: none)."""
        return self._stamps[-1] if self._stamps else -math.inf

    def beyond(self, stamp: float) -> bool:
        """Whether ``stamp`` is further from the latest stamp than poses are kept: a reading on
        another clock, not one a little before the first pose or after the latest."""
        return bool(self._stamps) and abs(stamp - self._stamps[-1]) > self.keep_s

    def clear(self) -> None:
        self._stamps.clear()
        self._poses.clear()

    def add(self, stamp: float, pose: Pose2) -> None:
        """A pose at ``stamp``; the latest stamp again replaces its pose, an earlier one (a
        restarted clock) starts the history again."""
        if self._stamps and stamp <= self._stamps[-1]:
            if stamp == self._stamps[-1]:
                self._poses[-1] = pose
                return
            self.clear()
        self._stamps.append(stamp)
        self._poses.append(pose)
        while self._stamps[0] < stamp - self.keep_s:
            self._stamps.popleft()
            self._poses.popleft()

    def at(self, stamp: float) -> Pose2 | None:
        """The pose at ``stamp``, the heading turned the short way between two samples; None
        when the history does not cover it (before the first sample kept, more than
        :attr:`ahead_s` after the latest, or between two samples more than :attr:`max_gap_s`
        apart)."""
        stamps = self._stamps
        if not stamps or stamp < stamps[0] or stamp > stamps[-1] + self.ahead_s:
            return None
        if stamp >= stamps[-1]:
            return self._poses[-1]
        i = bisect.bisect_right(stamps, stamp)
        a, b = stamps[i - 1], stamps[i]
        if stamp == a:
            x, y, theta = self._poses[i - 1]
            return float(x), float(y), float(theta)
        if b - a > self.max_gap_s:
            return None
        pose = interpolate(self._poses[i - 1], self._poses[i], (stamp - a) / (b - a))
        return float(pose[0]), float(pose[1]), float(pose[2])
