"""What the laser saw near the robot and no longer sees: scan points kept in the odometry frame.

A laser mounted ahead of the centre of a round robot, with a fan of 180 degrees, does not see
beside or behind the robot's own disc.  An avoider that looks only at the last scan forgets a box
as soon as the robot has turned away from it, while its disc is still a few centimetres from the
box's face: turning and driving on, it sweeps its disc into the corner it saw a moment ago (the
kinematic simulation of chapter 1's pair, :mod:`avoider_sim`, started inside the safety margin of a
box: 4 of 60 runs touched it).  :class:`ScanMemory` keeps the points of earlier scans that were
within :attr:`ScanMemory.near` of the robot, and gives back those that the laser cannot see from
where the robot is now; what the laser can see again, the latest scan tells (a point in view is
forgotten, so a person who walked away is not remembered in front of the robot).

A point is forgotten once the robot has moved :attr:`ScanMemory.keep_m` since it was seen (the path
driven plus the turns at the ``near`` lever, so that a half turn is 3.1 m: the most a kept point can
have moved against the robot), not after a time: what makes a kept point wrong is the odometry's
error, which grows with motion. Kept for 5 s, a box beside a robot that stood turning back and forth
for longer was forgotten, and the robot then drove its disc into the box's corner (the kinematic
benchmark with the SICK at 9600 baud, ``bench/guide_avoider.py``). Odometry drift over a few metres
is well below the avoider's safety distance.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

__all__ = ['LaserView', 'ScanMemory', 'moved']


@dataclasses.dataclass(frozen=True)
class LaserView:
    """Where the laser sees, in the robot frame: its position, its fan (bearings ``first`` to
    ``last``, rad, either order) and its range (m)."""

    x: float
    y: float
    first: float
    last: float
    max_range: float = math.inf

    def sees(self, points: NDArray) -> NDArray:
        """Whether each point (robot frame) is within the fan and the range."""
        dx, dy = points[:, 0] - self.x, points[:, 1] - self.y
        bearing = np.arctan2(dy, dx)
        low, high = min(self.first, self.last), max(self.first, self.last)
        # The bearing as near the middle of the fan as a turn allows (a fan may cross +-pi).
        middle = 0.5 * (low + high)
        bearing = middle + np.remainder(bearing - middle + math.pi, math.tau) - math.pi
        return (bearing >= low) & (bearing <= high) & (np.hypot(dx, dy) < self.max_range)


def _to_frame(pose: tuple[float, float, float], points: NDArray) -> NDArray:
    """Robot-frame ``points`` at ``pose`` in the odometry frame."""
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    return np.column_stack((x + c * points[:, 0] - s * points[:, 1], y + s * points[:, 0] + c * points[:, 1]))


def _to_robot(pose: tuple[float, float, float], points: NDArray) -> NDArray:
    """Odometry-frame ``points`` in the robot frame at ``pose``."""
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    dx, dy = points[:, 0] - x, points[:, 1] - y
    return np.column_stack((c * dx + s * dy, -s * dx + c * dy))


def moved(points: NDArray, before: tuple[float, float, float], after: tuple[float, float, float]) -> NDArray:
    """``points`` of the robot frame at the pose ``before`` in the robot frame at ``after`` (both
    poses in one frame): a scan taken at ``before`` as the robot at ``after`` has it."""
    return _to_robot(after, _to_frame(before, points)) if len(points) else points


class ScanMemory:
    """Points of earlier scans near the robot that the laser does not see now (module docstring).

    :param near: points farther than this (m) from the robot are not kept.
    :param keep_m: points are forgotten once the robot has moved this much (m of path, plus turns
        times ``near``) since they were seen.
    :param cell: points are kept one per square of this side (m), the newest.
    """

    def __init__(self, near: float = 1.0, keep_m: float = 4.0, cell: float = 0.02) -> None:
        self.near, self.keep_m, self.cell = near, keep_m, cell
        self.clear()

    def clear(self) -> None:
        """Forget everything (say, when the odometry frame changed)."""
        self._points = np.empty((0, 2))        # odometry frame
        self._seen = np.empty(0)               # the odometer when each point was seen
        self._latest: tuple[NDArray, float] | None = None      # the last scan's near points, its odometer
        self._pose: tuple[float, float, float] | None = None
        self.odometer = 0.0

    def _move_to(self, pose: tuple[float, float, float]) -> None:
        """Advance :attr:`odometer` by the motion from the last pose given to ``pose``."""
        if self._pose is not None:
            x, y, theta = self._pose
            self.odometer += math.hypot(pose[0] - x, pose[1] - y) + \
                self.near * abs(math.remainder(pose[2] - theta, math.tau))
        self._pose = pose

    def __len__(self) -> int:
        return len(self._points)

    def add(self, pose: tuple[float, float, float], points: NDArray, view: LaserView) -> None:
        """Take a scan: ``points`` in the robot frame at ``pose`` (odometry frame), seen by ``view``.
        What it could see of the remembered points is forgotten; its own near points are
        remembered once the next scan has come (until then the avoider has them as the scan)."""
        self._move_to(pose)
        if self._latest is not None:
            older, at = self._latest
            self._points = np.concatenate((older, self._points))
            self._seen = np.concatenate((np.full(len(older), at), self._seen))
        near = points[np.hypot(points[:, 0], points[:, 1]) < self.near] if len(points) else np.empty((0, 2))
        self._latest = (_to_frame(pose, near), self.odometer)
        self._prune(pose, view)

    def unseen(self, pose: tuple[float, float, float], view: LaserView) -> NDArray:
        """The remembered points (robot frame at ``pose``) within :attr:`near` that ``view``
        cannot see from ``pose``: to be avoided together with the latest scan."""
        self._move_to(pose)
        self._prune(pose, None)
        robot = _to_robot(pose, self._points)
        return robot[~view.sees(robot)] if len(robot) else robot

    def _prune(self, pose: tuple[float, float, float], view: LaserView | None) -> None:
        if not len(self._points):
            return
        robot = _to_robot(pose, self._points)
        keep = (self.odometer - self._seen <= self.keep_m) & (np.hypot(robot[:, 0], robot[:, 1]) < self.near)
        if view is not None:
            keep &= ~view.sees(robot)
        points, seen = self._points[keep], self._seen[keep]
        # One point per cell, the newest (the newest come first).
        cells = np.floor(points / self.cell).astype(np.int64)
        _, first = np.unique(cells[:, 0] * (1 << 32) + cells[:, 1], return_index=True)
        first.sort()
        self._points, self._seen = points[first], seen[first]
