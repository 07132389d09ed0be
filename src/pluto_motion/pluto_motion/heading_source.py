"""Where the driveModule's regulator reads the robot's heading.

Pluto 6.2 (T=1): the regulator's heading is "now relative to interface (3) (adjusted robot pose) of
the localModule", read through the loc proxy (:class:`pluto_nav.loc_proxy.LocProxy`).  When no pose
setter runs (setter 0: neither poseModule nor slamModule updates the localization) the drive falls
back to Dead-Reckoning (0), with a warning; when no localModule is heard at all, to the base's own
odometry (``<base>Motion``), which is the frame Pluto 6.1 first named ("angle defined by baseserver
interface ATRV2/Drive/Raw"), again with a warning.  A source is used only while it is fresh (a pose
taken in within :data:`FRESH_S` seconds).
"""

from __future__ import annotations

import time
from collections.abc import Callable

from pluto_nav.loc_proxy import LocProxy
from pluto_nav.streams import DEAD_RECKONING, NOBODY, POSE
from wurde_core import CommsManager
from wurde_core.interfaces import Egomotion

__all__ = ['FRESH_S', 'HeadingSource']

#: Seconds after which a pose that has not been renewed is no longer used.
FRESH_S = 1.0
_WARNINGS = {'Localization/Dead-Reckoning': 'no pose setter runs: the regulator holds its heading on '
                                            'Localization/Dead-Reckoning',
             'odometry': 'no localModule heard: the regulator holds its heading on the base odometry',
             None: 'no fresh heading: a regulator command stops the robot'}


class HeadingSource:
    """The robot's heading from the best fresh source; :attr:`source` names the one used last."""

    def __init__(self, manager: CommsManager, base: str, warn: Callable[[str], object]) -> None:
        self.loc = LocProxy(manager, (1 << DEAD_RECKONING) | (1 << POSE))
        self.motion = Egomotion(f'{base}Motion')
        manager.register_consumer(self.motion)
        self.warn = warn
        self.theta: dict[str, float] = {}
        self.heard: dict[str, float] = {}
        self.source: str | None = None

    def update(self) -> None:
        """Take in what arrived (every loop, so that freshness is the arrival's time)."""
        now = time.monotonic()
        for name, n in (('Localization/Pose', POSE), ('Localization/Dead-Reckoning', DEAD_RECKONING)):
            poses = self.loc.get_poses(n)
            if poses:
                self.theta[name], self.heard[name] = poses[-1].pose[3], now
        if self.motion.get_next_data():
            self.theta['odometry'] = self.motion.data.location.theta()
            self.heard['odometry'] = now

    def _fresh(self, name: str) -> bool:
        return time.monotonic() - self.heard.get(name, -float('inf')) <= FRESH_S

    def heading(self) -> float | None:
        """The heading (rad) or None when no source is fresh."""
        self.update()
        setter = self.loc.setter
        if setter is not None and setter != NOBODY and self._fresh('Localization/Pose'):
            chosen: str | None = 'Localization/Pose'
        elif self._fresh('Localization/Dead-Reckoning'):
            chosen = 'Localization/Dead-Reckoning'
        elif self._fresh('odometry'):
            chosen = 'odometry'
        else:
            chosen = None
        if chosen != self.source:
            if chosen in _WARNINGS:
                self.warn(_WARNINGS[chosen])
            self.source = chosen
        return None if chosen is None else self.theta[chosen]
