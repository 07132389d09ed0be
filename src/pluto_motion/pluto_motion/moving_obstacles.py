"""Things the laser sees moving (people, trolleys) and where they are about to be.

The laser guard and the goto's field react to where things are; a person crossing the robot's way
at 1 m/s is not in the way yet when the robot decides, and is under its bumper a second later.
:class:`MovingObstacles` follows small objects from scan to scan in the readings' continuous frame:
a scan's echoes are split into objects at gaps (:attr:`MovingSettings.gap`); an object no wider than
:attr:`MovingSettings.widest` (a wall is wider) is matched to the nearest one of the last scan that it
could have walked from, and its velocity is smoothed over the matches.  One that has moved at
:attr:`MovingSettings.moving` or faster over :attr:`MovingSettings.confirm` matches is moving;
:meth:`MovingObstacles.predicted` gives its echoes moved along its velocity over the next
:attr:`MovingSettings.horizon` seconds, which the avoidModule adds to what it avoids: the robot slows
or stops before the person's path, or steers behind them, instead of meeting them.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

__all__ = ['MovingObstacles', 'MovingSettings']

Pose = tuple[float, float, float]


@dataclasses.dataclass(frozen=True)
class MovingSettings:
    gap: float = 0.25           #: m between neighbouring echoes of one object
    widest: float = 1.2         #: m: a wider object is a wall, never followed
    nearest: int = 3            #: echoes an object needs
    max_range: float = 6.0      #: m: echoes beyond are not followed
    top_speed: float = 2.0      #: m/s: the fastest a followed object may have moved between scans
    moving: float = 0.3         #: m/s: slower is standing still (or the odometry's drift)
    confirm: int = 3            #: matches moving before an object counts as moving
    horizon: float = 1.5        #: s of its motion ahead that a moving object is avoided over
    steps: int = 6              #: predicted places over the horizon
    smoothing: float = 0.5      #: weight of the newest velocity


@dataclasses.dataclass
class _Track:
    centre: NDArray
    points: NDArray             # the echoes, readings' frame
    stamp: float
    velocity: NDArray = dataclasses.field(default_factory=lambda: np.zeros(2))
    moving_for: int = 0


def _objects(points: NDArray, settings: MovingSettings) -> list[NDArray]:
    """A scan's echoes (beam order) split into small objects."""
    near = np.hypot(points[:, 0], points[:, 1]) <= settings.max_range if len(points) else np.zeros(0, bool)
    objects, start = [], 0
    if len(points) < 2:
        return []
    breaks = np.flatnonzero(np.hypot(*np.diff(points, axis=0).T) > settings.gap) + 1
    for stop in [*breaks, len(points)]:
        part = points[start:stop]
        if len(part) >= settings.nearest and near[start:stop].all() \
                and math.dist(part[0], part[-1]) <= settings.widest:
            objects.append(part)
        start = stop
    return objects


def _to_frame(points: NDArray, pose: Pose) -> NDArray:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.column_stack((pose[0] + c * points[:, 0] - s * points[:, 1],
                            pose[1] + s * points[:, 0] + c * points[:, 1]))


def _to_robot(points: NDArray, pose: Pose) -> NDArray:
    dx, dy = points[:, 0] - pose[0], points[:, 1] - pose[1]
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.column_stack((c * dx + s * dy, -s * dx + c * dy))


class MovingObstacles:
    """Feed every scan to :meth:`scan`; :meth:`predicted` gives the moving objects' next places."""

    def __init__(self, settings: MovingSettings = MovingSettings()) -> None:
        self.settings = settings
        self.tracks: list[_Track] = []

    def forget(self) -> None:
        """The readings' frame changed: what was followed is in another frame."""
        self.tracks = []

    def scan(self, points: NDArray, pose: Pose | None, stamp: float) -> None:
        """A scan's echoes (robot frame, beam order) taken at ``pose`` (readings' frame) at ``stamp``."""
        if pose is None:
            self.tracks = []
            return
        s = self.settings
        found = [_to_frame(o, pose) for o in _objects(np.asarray(points, dtype=float).reshape(-1, 2), s)]
        tracks, taken = [], set()
        for echoes in found:
            centre = echoes.mean(axis=0)
            best, best_d = None, math.inf
            for i, old in enumerate(self.tracks):
                dt = stamp - old.stamp
                d = float(np.hypot(*(centre - old.centre)))
                if i not in taken and 0.0 < dt and d <= s.top_speed * dt + s.gap and d < best_d:
                    best, best_d = i, d
            track = _Track(centre, echoes, stamp)
            if best is not None:
                taken.add(best)
                old = self.tracks[best]
                seen = (centre - old.centre) / (stamp - old.stamp)
                track.velocity = s.smoothing * seen + (1.0 - s.smoothing) * old.velocity
                fast = float(np.hypot(*track.velocity)) >= s.moving
                track.moving_for = old.moving_for + 1 if fast else 0
            tracks.append(track)
        self.tracks = tracks

    def moving(self) -> list[_Track]:
        return [t for t in self.tracks if t.moving_for >= self.settings.confirm]

    def predicted(self, pose: Pose | None) -> NDArray:
        """The moving objects' echoes where they will be over the horizon, in the robot frame at
        ``pose`` (readings' frame); none without a pose."""
        tracks = self.moving()
        if pose is None or not tracks:
            return np.zeros((0, 2))
        s = self.settings
        ahead = np.linspace(s.horizon / s.steps, s.horizon, s.steps)
        places = [t.points + t.velocity * when for t in tracks for when in ahead]
        return _to_robot(np.concatenate(places), pose)
