"""Localize's gaussian initialization (Programming with CARMEN 4.2) on Pluto's localization.

The localModule takes a user's robot pose (setter -1) only while no estimator holds the pose.
While the poseModule holds it, Pluto 7.1's way is followed, one step per turn of the program's
loop (never blocking): stop the pose thread (``pose/status`` element[0] = 0), wait until the setter
is released, write the pose, wait until the localization shows it, start the thread again.  While
the slamModule holds it the pose is written as it is (refused, and logged, by the localModule):
restarting the slamModule would begin a new map.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from wurde_core import CommsManager
from wurde_core.interfaces import FVectorState

from pluto_nav.loc_proxy import LocProxy
from pluto_nav.streams import NOBODY, POSE, POSE_SETTER, USER_SETTER

__all__ = ['Initializer', 'POSE_STATUS']

#: The poseModule's status stream (Pluto 7.1).
POSE_STATUS = 'pose/status'


class Initializer:
    """Pending initializations of ``manager``'s program; :meth:`update` every turn."""

    def __init__(self, manager: CommsManager) -> None:
        """Read the localization's pose and the poseModule's status.

        :param manager: the program's manager.
        """
        self.loc = LocProxy(manager, 1 << POSE)
        self.status: Any = FVectorState(POSE_STATUS)
        manager.register_consumer(self.status)
        self.pending: tuple[tuple[float, float, float], np.ndarray] | None = None
        self.stage = ''
        self._request: list[int] | None = None

    def start(self, pose: tuple[float, float, float], covariance: np.ndarray) -> None:
        """Set ``pose`` (x, y, theta) with ``covariance`` (3x3) as soon as the rules allow (once
        the localModule's setter is known).

        :param pose: the robot pose (x, y in m, theta in rad, map frame).
        :param covariance: its 3x3 covariance (m², rad²); replaces a pose still pending.
        """
        self.pending, self.stage = (pose, covariance), 'ask'
        self.update()

    def _thread(self, run: bool) -> None:
        self._request = [1 if run else 0]

    def _send_request(self) -> None:
        """The status request, once the poseModule's reader is matched (a request channel keeps
        nothing for a reader that comes later)."""
        if self._request is not None and self.status.peers('request'):
            self.status.requests.element.set_value(self._request)
            if self.status.publish_request():
                self._request = None

    def update(self) -> None:
        """One step of the procedure."""
        self.loc.update()
        while self.status.get_next_data():
            pass
        self._send_request()
        setter = self.loc.setter
        if self.stage == 'ask' and self.pending is not None and setter is not None:
            if setter == POSE_SETTER:
                self._thread(False)
                self.stage = 'released'
            else:
                self._write()
                self.stage = ''
        elif self.stage == 'released' and setter is not None and setter <= NOBODY:
            self._write()
            self.stage = 'shown'
        elif self.stage == 'shown' and setter == USER_SETTER:
            self._thread(True)
            self.stage = ''
        self._send_request()

    def _write(self) -> None:
        assert self.pending is not None
        pose, covariance = self.pending
        self.loc.set_pose(pose, USER_SETTER, covariance=covariance)
        self.pending = None
