"""The avoidModule's laser protection (Pluto 6.2: "The avoidModule also provides laser collision
protection similar to the driveModule sonar protection ... element[0]=6 indicates laser slow/stop";
"element[0]=7 indicates the laser scanner has had a fatal error and is rebooting").

:class:`LaserGuard` slows, then stops, motion towards what the laser sees: the points in the robot's
swept corridor ahead (forward travel only: the laser looks forward, from -90 to +90 degrees) limit
the linear speed by the free distance the round footprint has before it touches the nearest of them.
The allowed speed falls linearly from the speed asked for at ``slow`` metres of free distance to zero
at ``stop`` metres; under ``creep`` m/s it is a stop, as the drive's sonar guard does.  Turning is
never limited: the footprint is round.

:class:`LaserWatch` decides whether the laser can be trusted at all: a scan with negative ranges is
the SICK's fatal error ("all data is set to -1", Pluto 8.1), and no scan for longer than the laser's
own period allows (:data:`STALE_PERIODS` periods, at least :data:`STALE_MIN_S` more than one) is a
dead laser.  Either is code 7 and a stop (fail closed) while laser protection is on.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

__all__ = ['LASER_FATAL', 'LASER_SLOW', 'STALE_MIN_S', 'STALE_PERIODS', 'GuardLimits', 'LaserGuard', 'LaserWatch',
           'free_distance']

#: element[0] codes of ``avoidance/status`` (Pluto 6.2).
LASER_SLOW, LASER_FATAL = 6, 7
#: A laser is stale after this many of its scan periods without a scan ...
STALE_PERIODS = 3.0
#: ... and never sooner than this many seconds more than one period (jitter of a loaded machine).
STALE_MIN_S = 0.25


@dataclasses.dataclass(frozen=True)
class GuardLimits:
    """The footprint and the free distances (m, from the footprint's edge) that slow and stop."""

    radius: float = 0.35
    #: lateral margin added to the footprint for the corridor (m)
    margin: float = 0.05
    stop: float = 0.15
    slow: float = 1.0
    creep: float = 0.05

    def __post_init__(self) -> None:
        if not 0.0 <= self.stop < self.slow:
            raise ValueError(f'the laser guard needs 0 <= stop < slow, not stop {self.stop}, '
                             f'slow {self.slow}')


def free_distance(points: np.ndarray, radius: float, margin: float = 0.0,
                  direction: float = 0.0) -> float:
    """How far a disc of ``radius`` at the origin can move along ``direction`` (rad, robot frame)
    before it comes within ``margin`` of one of ``points`` ((N, 2), robot frame); inf when nothing
    is in its way, 0 when a point is already that close."""
    if len(points) == 0:
        return math.inf
    c, s = math.cos(direction), math.sin(direction)
    along = points[:, 0] * c + points[:, 1] * s
    across = -points[:, 0] * s + points[:, 1] * c
    reach = radius + margin
    ahead = (np.abs(across) < reach) & (along > -reach)
    if not np.any(ahead):
        return math.inf
    gap = along[ahead] - np.sqrt(reach * reach - across[ahead] ** 2)
    return max(0.0, float(np.min(gap)))


class LaserGuard:
    """The speed the laser allows."""

    def __init__(self, limits: GuardLimits = GuardLimits()) -> None:
        self.limits = limits

    def fraction(self, points: np.ndarray, direction: float = 0.0) -> float:
        """1 when nothing within ``slow`` is in the way along ``direction``, falling to 0 at ``stop``."""
        lim = self.limits
        gap = free_distance(points, lim.radius, lim.margin, direction)
        if gap >= lim.slow:
            return 1.0
        return max(0.0, (gap - lim.stop) / (lim.slow - lim.stop))

    def limit(self, tv: float, points: np.ndarray, wanted: float | None = None) -> tuple[float, int]:
        """``tv`` slowed for the laser points ahead and the code (6 when slowed or stopped, 0 when
        not).  The allowed speed is ``wanted`` (the speed asked for; default ``tv``) times the free
        distance's fraction, a stop under ``creep``; ``tv`` is cut to it.  A goto passes its maximum
        speed as ``wanted``: it has slowed for the same obstacles already, and slowing twice made a
        crawl under the creep speed, a stop short of goals near walls.  Backward motion is not the
        laser's to judge."""
        if tv <= 0.0:
            return tv, 0
        f = self.fraction(points)
        if f >= 1.0:
            return tv, 0
        cap = (tv if wanted is None else wanted) * f
        if cap < self.limits.creep:
            cap = 0.0
        return (tv, 0) if cap >= tv else (cap, LASER_SLOW)


class LaserWatch:
    """Whether the laser is alive: scans arrive (:meth:`scan`) and :meth:`failure` says why not."""

    def __init__(self, stale_s: float | None = None) -> None:
        """:param stale_s: a fixed staleness limit (s); None: from the measured scan period."""
        self.fixed = stale_s
        self.arrived = -math.inf
        self.stamp: float | None = None
        self.period: float | None = None
        self.fatal = False

    def scan(self, ranges: Sequence[float], stamp: float, now: float) -> None:
        """A scan arrived at ``now`` (monotonic s), taken at ``stamp`` (the laser's clock)."""
        self.fatal = bool(len(ranges)) and min(ranges) < 0.0
        if self.stamp is not None and stamp > self.stamp:
            gap = stamp - self.stamp
            self.period = gap if self.period is None else min(self.period, gap)
        self.stamp, self.arrived = stamp, now

    @property
    def stale_after(self) -> float:
        """Seconds without a scan after which the laser is dead."""
        if self.fixed is not None:
            return self.fixed
        period = self.period if self.period is not None else 0.2
        return max(STALE_PERIODS * period, period + STALE_MIN_S)

    def failure(self, now: float) -> str | None:
        """None when the laser is fine, else why it is not."""
        if self.arrived == -math.inf:
            return 'no scan yet'
        if now - self.arrived > self.stale_after:
            return f'no scan for {now - self.arrived:.2f} s (limit {self.stale_after:.2f} s)'
        if self.fatal:
            return 'fatal error (negative ranges)'
        return None
