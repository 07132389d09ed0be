"""Things the laser sees moving (people, trolleys): where they are and how fast they go.

The laser guard and the goto's field react to where things are; a person crossing the robot's way
at 1 m/s is not in the way yet when the robot decides, and is under its bumper a second later.
:class:`MovingObstacles` follows small objects from scan to scan in the readings' continuous frame:
a scan's echoes are split into objects at gaps (:attr:`MovingSettings.gap`); an object no wider than
:attr:`MovingSettings.widest` (a wall is wider), not flat (a piece of wall) and in front of what is
beside it is matched to the nearest one of the last scan that it could have walked from, and its
velocity is a straight line fitted to its last :attr:`MovingSettings.history` centres.  One that has
moved at :attr:`MovingSettings.moving` or faster over :attr:`MovingSettings.confirm` matches is a
walker, and moving whenever it moves again after a pause or a turn; one that leaves the laser's view
beside the robot is kept where its velocity takes it for :attr:`MovingSettings.coast` scans.
:meth:`MovingObstacles.walkers` gives the moving ones, each a disc round its echoes, to
:func:`~pluto_motion.passage.passage_speed`, which times the robot's passage past them.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from .passage import Walker
from .scan_points import wrap

__all__ = ['MovingObstacles', 'MovingSettings', 'View']

Pose = tuple[float, float, float]
#: A laser's view: its place (x, y) and the bearings of its first and last beams, robot frame.
View = tuple[float, float, float, float]
#: rad: an object with an echo this near an edge of the laser's view is cut by it
EDGE = math.radians(3.0)


@dataclasses.dataclass(frozen=True)
class MovingSettings:
    gap: float = 0.25           #: m between neighbouring echoes of one object
    widest: float = 1.2         #: m: a wider object is a wall, never followed
    flat: float = 0.05          #: m: echoes all this near the line between its ends are a piece of wall
    nearest: int = 3            #: echoes an object needs
    max_range: float = 6.0      #: m: echoes beyond are not followed
    top_speed: float = 2.0      #: m/s: the fastest a followed object may have moved between scans
    moving: float = 0.3         #: m/s: slower is standing still (or the odometry's drift)
    confirm: int = 3            #: matches moving before an object counts as moving
    history: int = 3            #: the last centres a track's velocity is fitted to
    body: float = 0.25          #: m: the least radius a walker's body is given (a person's)
    coast: int = 5              #: scans a walker unseen (beside the robot, out of the laser's view)
                                #: is still expected where its velocity takes it


@dataclasses.dataclass
class _Track:
    centre: NDArray
    points: NDArray             # the echoes, readings' frame
    stamp: float
    velocity: NDArray = dataclasses.field(default_factory=lambda: np.zeros(2))
    moving_for: int = 0
    #: seen moving once: a person, followed as one while they pause, turn or slow
    walked: bool = False
    #: the body: a disc round the echoes, whose centre lies behind them as seen from the robot
    body: NDArray = dataclasses.field(default_factory=lambda: np.zeros(2))
    radius: float = 0.0
    unseen: int = 0
    #: (stamp, x, y) of the last centres, oldest first
    seen: list[tuple[float, float, float]] = dataclasses.field(default_factory=list)


def _objects(points: NDArray, settings: MovingSettings) -> list[NDArray]:
    """A scan's echoes (beam order) split into small objects in front of what is behind them.

    Echoes that lie on a line are a piece of wall (a person's body is round or has corners).  An
    object whose neighbouring echo at either end is nearer than its own end is cut by something in
    front of it (a wall behind a person, a wall seen at a grazing angle split where its echoes thin
    out).  The visible part of either, and so its centre, moves as the robot moves: both are left out.
    """
    if len(points) < 2:
        return []
    distance = np.hypot(points[:, 0], points[:, 1])
    near = distance <= settings.max_range
    objects, start = [], 0
    breaks = np.flatnonzero(np.hypot(*np.diff(points, axis=0).T) > settings.gap) + 1
    for stop in [*breaks, len(points)]:
        part = points[start:stop]
        in_front = (start == 0 or distance[start - 1] > distance[start]) \
            and (stop == len(points) or distance[stop] > distance[stop - 1])
        if len(part) >= settings.nearest and near[start:stop].all() and in_front \
                and math.dist(part[0], part[-1]) <= settings.widest and not _flat(part, settings.flat):
            objects.append(part)
        start = stop
    return objects


def _cut(echoes: NDArray, view: View) -> bool:
    """Whether an object's ends (robot frame) lie at an edge of the laser's ``view``."""
    x, y, first, last = view
    for px, py in (echoes[0], echoes[-1]):
        bearing = math.atan2(py - y, px - x)
        for edge in (first, last):
            if abs(wrap(bearing - edge)) < EDGE:
                return True
    return False


def _flat(part: NDArray, tolerance: float) -> bool:
    """Whether every echo of ``part`` is within ``tolerance`` of the line through its ends."""
    chord = part[-1] - part[0]
    length = math.hypot(*chord)
    if length == 0.0:
        return True
    off = np.abs(chord[0] * (part[:, 1] - part[0, 1]) - chord[1] * (part[:, 0] - part[0, 0])) / length
    return bool(off.max() < tolerance)


def _body(echoes: NDArray, pose: Pose, settings: MovingSettings) -> tuple[NDArray, float]:
    """The disc of a body whose echoes (readings' frame) the robot at ``pose`` saw: the echoes lie
    on the near half of its rim, so its centre is half a radius behind their mean."""
    spread = float(np.max(np.hypot(*(echoes[:, None, :] - echoes[None, :, :]).transpose(2, 0, 1))))
    radius = min(max(0.5 * spread, settings.body), 0.5 * settings.widest)
    centre = echoes.mean(axis=0)
    away = centre - np.asarray(pose[:2])
    return centre + away / max(float(np.hypot(*away)), 1e-6) * 0.5 * radius, radius


def _fitted_velocity(seen: list[tuple[float, float, float]]) -> NDArray:
    """The velocity a straight line through the centres ``seen`` (stamp, x, y) has."""
    t, x, y = np.asarray(seen).T
    t = t - t.mean()
    return np.array([t @ (x - x.mean()), t @ (y - y.mean())]) / float(t @ t)


def _to_frame(points: NDArray, pose: Pose) -> NDArray:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.column_stack((pose[0] + c * points[:, 0] - s * points[:, 1],
                            pose[1] + s * points[:, 0] + c * points[:, 1]))


def _to_robot(points: NDArray, pose: Pose) -> NDArray:
    dx, dy = points[:, 0] - pose[0], points[:, 1] - pose[1]
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.column_stack((c * dx + s * dy, -s * dx + c * dy))


class MovingObstacles:
    """Feed every scan to :meth:`scan`; :meth:`walkers` gives the moving objects."""

    def __init__(self, settings: MovingSettings = MovingSettings()) -> None:
        self.settings = settings
        self.tracks: list[_Track] = []

    def forget(self) -> None:
        """The readings' frame changed: what was followed is in another frame."""
        self.tracks = []

    def scan(self, points: NDArray, pose: Pose | None, stamp: float, view: View | None = None) -> None:
        """A scan's echoes (robot frame, beam order) taken at ``pose`` (readings' frame) at ``stamp``.
        ``view``: where the laser is and the bearings of its first and last beams (robot frame); an
        object at either edge is cut by the field of view (a walker leaving it beside the robot
        seems to slow and turn), and its track goes on unseen."""
        if pose is None:
            self.tracks = []
            return
        s = self.settings
        objects = _objects(np.asarray(points, dtype=float).reshape(-1, 2), s)
        found = [_to_frame(o, pose) for o in objects if view is None or not _cut(o, view)]
        tracks, taken, moving = [], set(), {id(t) for t in self.moving()}
        for echoes in found:
            centre = echoes.mean(axis=0)
            best, best_d = None, math.inf
            for i, old in enumerate(self.tracks):
                dt = stamp - old.stamp
                d = float(np.hypot(*(centre - old.centre)))
                if i not in taken and 0.0 < dt and d <= s.top_speed * dt + s.gap and d < best_d:
                    best, best_d = i, d
            track = _Track(centre, echoes, stamp, seen=[(stamp, float(centre[0]), float(centre[1]))])
            track.body, track.radius = _body(echoes, pose, s)
            if best is not None:
                taken.add(best)
                old = self.tracks[best]
                track.seen = old.seen[-(s.history - 1):]
                track.seen.append((stamp, float(centre[0]), float(centre[1])))
                track.velocity = _fitted_velocity(track.seen)
                fast = float(np.hypot(*track.velocity)) >= s.moving
                track.moving_for = old.moving_for + 1 if fast else 0
                track.walked = old.walked or track.moving_for >= s.confirm
            tracks.append(track)
        for i, old in enumerate(self.tracks):
            if i not in taken and id(old) in moving and old.unseen < s.coast and stamp > old.stamp:
                moved = old.velocity * (stamp - old.stamp)
                tracks.append(dataclasses.replace(old, centre=old.centre + moved, points=old.points + moved,
                                                  body=old.body + moved, stamp=stamp, unseen=old.unseen + 1))
        self.tracks = tracks

    def moving(self) -> list[_Track]:
        """The tracks moving now: seen moving for :attr:`MovingSettings.confirm` scans once, and
        again since the last scan (one who paused is known at once when they walk on).  One who
        stands is the laser guard's and the goto's to keep clear of, as any obstacle."""
        return [t for t in self.tracks if t.walked and t.moving_for > 0]

    def walkers(self, pose: Pose | None) -> list[Walker]:
        """The moving objects in the robot frame at ``pose`` (readings' frame): their bodies and
        velocities, for :func:`~pluto_motion.passage.passage_speed`; none without a pose."""
        if pose is None:
            return []
        c, s = math.cos(pose[2]), math.sin(pose[2])
        return [Walker(_to_robot(t.body[None, :], pose)[0], t.radius,
                       np.array([c * t.velocity[0] + s * t.velocity[1], -s * t.velocity[0] + c * t.velocity[1]]))
                for t in self.moving()]
