"""A base's odometry in one frame for as long as its consumer runs, through restarts of the base.

A restarted base driver counts its odometry from zero again (the dummy base does, as a real base
driver does, see :mod:`wurde_drivers.sim.dummies.base`).  A module that holds a goal or a heading
in the odometry frame (the laserAvoider's relative goal, the SynchroMover's vector, the goto of a
drive chain on the odometry fall-back) would, after such a restart, go to the right place in the
wrong frame: in a CI run the MCP restarted a starved base 1.2 m into a 5 m move, and the avoider
drove on to a goal 1.6 m off its true one.

The rule is the localModule's (:mod:`pluto_nav.dead_reckoning`): the first sample of a new base
process (another ``header.session``, :class:`wurde_core.sender_watch.SenderWatch`) is a restart of
the odometry, which the new process counts from zero where the old one left the robot (as no
motion if its reading is further than the robot could have gone since the last sample); an
increment no robot could make is a restart that counts as no motion.  The poses of the new
process are composed onto the last pose of the old one, so that the consumer's frame
stays the one it started in.
"""

from __future__ import annotations

import math
from typing import Any

from wurde_core.sender_watch import SenderWatch

from .dead_reckoning import possible
from .geometry import compose, inverse, relative

__all__ = ['ContinuousOdometry']


class ContinuousOdometry:
    """Feed it each Egomotion sample (:meth:`take`); :attr:`pose` is the robot in the frame of the
    first sample's base process, :attr:`resets` how many restarts of the base it has bridged."""

    def __init__(self) -> None:
        self.pose: tuple[float, float, float] | None = None
        self.resets = 0
        #: The last restart bridged: (the last pose before it in this frame, the new process's
        #: first pose in its own frame), for the consumer's log.
        self.bridge: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None
        self._offset = (0.0, 0.0, 0.0)
        self._raw: tuple[float, float, float] | None = None
        self._stamp = -math.inf
        self._sender = SenderWatch()

    def take(self, data: Any) -> tuple[float, float, float]:
        """Take one Egomotion data sample (``location``, ``timestamp``, a numbered header);
        returns the pose in this consumer's frame."""
        location = data.location
        raw = (float(location.x()), float(location.y()), float(location.theta()))
        new_sender = self._sender.take(data.ros_message().header)
        stamp = float(data.timestamp.get_seconds())
        if self._raw is not None and self.pose is not None and (new_sender or self._jumped(raw, stamp)):
            # Where the new process's zero is in this frame: where the old one left the robot,
            # if it could have driven to its first reading since (the dead reckoning's rule);
            # else the robot has not moved meanwhile.
            from_zero = new_sender and possible(raw, max(stamp - self._stamp, 1e-6))
            self._offset = self.pose if from_zero else tuple(compose(self.pose, inverse(raw)))
            self.resets += 1
            self.bridge = (self.pose, raw)
        self._raw, self._stamp = raw, stamp
        x, y, theta = compose(self._offset, raw)
        self.pose = (float(x), float(y), float(theta))
        return self.pose

    def _jumped(self, raw: tuple[float, float, float], stamp: float) -> bool:
        assert self._raw is not None  # called once a sample was taken
        return not possible(relative(self._raw, raw), max(stamp - self._stamp, 1e-6))

    def describe_bridge(self) -> str:
        """The last restart bridged, for a log line: where the old frame ended, where the new began."""
        if self.bridge is None:
            return 'no restart bridged'
        (x, y, theta), (u, v, phi) = self.bridge
        return (f'last pose ({x:.3f}, {y:.3f}, {theta:.3f}) continued from the new process\'s '
                f'({u:.3f}, {v:.3f}, {phi:.3f})')
