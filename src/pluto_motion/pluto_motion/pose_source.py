"""Where the movement chain reads the robot's pose (x, y, theta).

Pluto 6.2: the avoidModule's goto position and the drive's regulator heading are "relative to
interface (3) (adjusted robot pose) of the localModule", read through the loc proxy
(:class:`pluto_nav.loc_proxy.LocProxy`).  When no pose setter runs (setter 0: neither poseModule nor
slamModule updates the localization) the source falls back to Dead-Reckoning (0), with a warning;
when no localModule is heard at all, to the base's own odometry (``<base>Motion``, whose frame starts
at the robot's start: the frame Pluto 6.1 first named, "angle defined by baseserver interface
ATRV2/Drive/Raw", kept through a restart of the base by :mod:`pluto_nav.continuous_odometry`), again
with a warning.  A source is used only while it is fresh (a pose taken in
within :data:`FRESH_S` seconds).  Each change of source is logged once.  The base odometry is a
fall-back only where no localModule runs: never once one has been heard (a localModule restarting
is waited for — its frame is the map's, the odometry's is not, and a goto steered on the wrong one
drives into a wall), nor while one is matched on the graph, nor in the first :data:`START_GRACE_S`
seconds (a new process discovers the localModule and the base in no fixed order).

Each source's poses of the last seconds are kept by their stamps (:class:`pluto_nav.pose_history.
PoseHistory`, the robot's clock, which the laser and the sonar stamp their readings with too), so
that :meth:`PoseSource.pose_at` can say where the robot was when a reading was taken, in the frame
of :meth:`PoseSource.frame`.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from pluto_nav.continuous_odometry import ContinuousOdometry
from pluto_nav.loc_proxy import LocProxy
from pluto_nav.pose_history import PoseHistory
from pluto_nav.streams import DEAD_RECKONING, NOBODY, POSE
from wurde_core import CommsManager
from wurde_core.interfaces import Egomotion

__all__ = ['FRESH_S', 'ODOMETRY', 'START_GRACE_S', 'PoseSource']

#: Seconds after which a pose that has not been renewed is no longer used.
FRESH_S = 1.0
#: Seconds after its start before a source falls back to the base odometry.
START_GRACE_S = 5.0
#: The name of the last fall-back: the base's odometry.
ODOMETRY = 'odometry'
_STREAMS = (('Localization/Pose', POSE), ('Localization/Dead-Reckoning', DEAD_RECKONING))


class PoseSource:
    """The robot's pose from the best fresh source; :attr:`source` names the one used last.

    ``user`` says what the pose is for in the warnings ("the regulator holds its heading",
    "the goto steers"), so that a log names the module's consequence of a fall-back.
    """

    def __init__(self, manager: CommsManager, base: str, warn: Callable[[str], object], *, user: str,
                 localization_only: bool = False) -> None:
        """:param localization_only: never fall back to the base odometry, whose frame starts where
            the base did and is not the map's: a module that plans on a map waits for the
            localModule instead."""
        self.localization_only = localization_only
        # Queue mode: every sample reaches the histories, not one per loop of the module.
        self.loc = LocProxy(manager, (1 << DEAD_RECKONING) | (1 << POSE), queue_mode=True)
        self.motion = Egomotion(f'{base}Motion')
        self.motion.set_queue_mode(True)
        manager.register_consumer(self.motion)
        #: The odometry fall-back in one frame through restarts of the base.
        self.odometry = ContinuousOdometry()
        self.warn = warn
        self.warnings = {'Localization/Dead-Reckoning': f'no pose setter runs: {user} on '
                                                        'Localization/Dead-Reckoning',
                         ODOMETRY: f'no localModule heard: {user} on the base odometry',
                         None: ('no fresh pose from the localModule: waiting for one' if localization_only
                                else 'no fresh pose: the robot stops until one comes')}
        self.poses: dict[str, tuple[float, float, float]] = {}
        self.histories = {name: PoseHistory()
                          for name in ('Localization/Pose', 'Localization/Dead-Reckoning', ODOMETRY)}
        self.heard: dict[str, float] = {}
        self.source: str | None = None
        self.started = time.monotonic()

    def update(self) -> None:
        """Take in what arrived (every loop, so that freshness is the arrival's time)."""
        now = time.monotonic()
        for name, n in _STREAMS:
            poses = self.loc.get_poses(n)
            for sample in poses:
                self.histories[name].add(sample.stamp, sample.xytheta)
            if poses:
                self.poses[name], self.heard[name] = poses[-1].xytheta, now
        while self.motion.get_next_data():
            self.poses[ODOMETRY], self.heard[ODOMETRY] = self.odometry.take(self.motion.data), now
            self.histories[ODOMETRY].add(self.motion.data.timestamp.get_seconds(), self.poses[ODOMETRY])

    def _fresh(self, name: str) -> bool:
        return time.monotonic() - self.heard.get(name, -float('inf')) <= FRESH_S

    def pose(self) -> tuple[float, float, float] | None:
        """(x, y, theta) in m and rad, or None when no source is fresh."""
        self.update()
        setter = self.loc.setter
        if setter is not None and setter != NOBODY and self._fresh('Localization/Pose'):
            chosen: str | None = 'Localization/Pose'
        elif self._fresh('Localization/Dead-Reckoning'):
            chosen = 'Localization/Dead-Reckoning'
        elif self._fresh(ODOMETRY) and self._odometry_allowed():
            chosen = ODOMETRY
        else:
            chosen = None
        if chosen != self.source:
            if chosen in self.warnings:
                self.warn(self.warnings[chosen])
            self.source = chosen
        return None if chosen is None else self.poses[chosen]

    def _odometry_allowed(self) -> bool:
        """Whether the base odometry may stand in for the localization (see the module's text)."""
        if self.localization_only or any(name in self.heard for name, _ in _STREAMS):
            return False
        if time.monotonic() - self.started < START_GRACE_S:
            return False
        return not any(self.loc.streams[n].peers('data') for _, n in _STREAMS)

    def frame(self) -> str | None:
        """The fresh source that never jumps, to move readings with the robot by: Dead-Reckoning,
        else the base odometry (Localization/Pose jumps when a pose setter corrects it, and a
        correction is not motion); None when neither is fresh."""
        self.update()
        for name in ('Localization/Dead-Reckoning', ODOMETRY):
            if self._fresh(name):
                return name
        return None

    def pose_at(self, source: str, stamp: float) -> tuple[float, float, float] | None:
        """Where ``source`` had the robot at ``stamp`` (the robot's clock), interpolated; None
        when its kept poses do not reach ``stamp``."""
        return self.histories[source].at(stamp)

    def beyond(self, source: str, stamp: float) -> bool:
        """Whether ``stamp`` is further from ``source``'s stamps than they are kept: a reading on
        another clock, not just one a little before the first pose."""
        return self.histories[source].beyond(stamp)
