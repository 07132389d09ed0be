"""The transform from a module's odometry frame to another module's frame, measured while the robot stands.

The laserAvoider drives chapter 1's mover through its Navigator stream (guide 1.1.5), whose goals
are points in the navigator's own frame: the mover's odometry frame, or a map frame for a map-based
navigator.  The two odometry frames agree as long as both modules saw the same samples, but a
base restart is bridged by each module at the last sample it took of the old process
(:mod:`pluto_nav.continuous_odometry`), and a killed process's last message can reach one module
and not the other.  The two frames then stand centimetres apart: the mover stands at the
avoider's goal in its own frame, short of it in the avoider's, and the avoider asks for the same
point for ever.

While the robot stands, the pose a navigator reports and the module's own pose are the same place
whatever samples each was computed from, so their difference is the transform between the frames,
exact to the odometry's resolution.  It is measured from every navigator status that arrives
after the robot has stood for :data:`STILL_S`, and it stays as measured while the robot moves.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from pluto_nav.geometry import compose, inverse

__all__ = ['STILL_M', 'STILL_RAD', 'STILL_S', 'FrameLink']

#: The robot stands when its pose has moved less than STILL_M and turned less than STILL_RAD over
#: STILL_S seconds; a status that comes after that is one of the standing robot (the mover
#: publishes its status at least once a second, from the sample of its last loop).
STILL_S = 0.5
STILL_M = 0.002
STILL_RAD = 0.005
Pose2 = tuple[float, float, float]


def _pose2(pose: Iterable[float]) -> Pose2:
    """A pose of three numbers (numpy's or not) as a tuple of floats."""
    x, y, theta = pose
    return float(x), float(y), float(theta)


class FrameLink:
    """Feed it the module's own poses (:meth:`own`) and the other frame's reports of the same
    robot (:meth:`other`); :meth:`to_other` takes a point of the own frame into the other."""

    def __init__(self) -> None:
        #: The other frame's pose of the own frame's origin (identity until first measured).
        self.transform: Pose2 = (0.0, 0.0, 0.0)
        self._pose: Pose2 | None = None
        self._still_pose: Pose2 | None = None
        self._still_since = math.inf

    def own(self, pose: Pose2, now: float) -> None:
        """The module's pose at monotonic time ``now``."""
        self._pose = pose
        if self._still_pose is None or (math.dist(pose[:2], self._still_pose[:2]) > STILL_M
                                        or abs(math.remainder(pose[2] - self._still_pose[2], math.tau)) > STILL_RAD):
            self._still_pose, self._still_since = pose, now

    def other(self, pose: Pose2, now: float) -> Pose2 | None:
        """The other frame's pose of the robot, taken at ``now``; returns the transform's change
        (None: not measured, the robot was not standing)."""
        if self._pose is None or now - self._still_since < STILL_S:
            return None
        transform = _pose2(compose(pose, inverse(self._pose)))
        change = _pose2(compose(inverse(self.transform), transform))
        self.transform = transform
        return change

    def to_other(self, x: float, y: float) -> tuple[float, float]:
        """The point ``(x, y)`` of the own frame in the other frame."""
        tx, ty, _ = compose(self.transform, (x, y, 0.0))
        return float(tx), float(ty)
