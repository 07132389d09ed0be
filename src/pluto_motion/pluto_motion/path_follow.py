"""Following a planned path: pure pursuit over the plan's waypoints, for the motionModule's moveto
on a map.

The planner's path keeps the robot's clearance from every wall (a 0.9 m door is passed down its
middle with 0.1 m to spare each side), so along it the motionModule does not steer by repulsion — the
avoid goto's vector summation turns the robot towards a jamb it is passing and stops it there — but
steers for a point ``lookahead`` metres further along the path, through the avoidModule's
regulator with laser protection (cmdFlags 21: the laser still slows and stops the robot for what the
map does not show).  It turns on the spot while the heading is more than ``turn_first`` off, and
slows on the last metre.  :class:`Progress` tells when the robot has stopped getting nearer the
goal along the path (something in the way): the moveto then replans round what the laser sees.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

from .scan_points import wrap

__all__ = ['FollowSettings', 'PathFollower', 'Progress']


@dataclasses.dataclass(frozen=True)
class FollowSettings:
    """Distances m, speeds m/s, angles rad, times s."""

    lookahead: float = 0.5
    turn_first: float = 0.35
    #: Where the map leaves less than ``narrow`` metres from the robot's centre to the nearest wall
    #: (a door: 0.45), the robot steers for a nearer point, turns on the spot sooner and slows, so
    #: that it passes down the middle and does not cut the corner into the door.
    narrow: float = 0.7
    narrow_lookahead: float = 0.25
    narrow_turn_first: float = 0.15
    narrow_speed: float = 0.25
    #: No ``progress`` metres nearer the goal along the path within ``patience`` s: stuck.
    progress: float = 0.2
    patience: float = 8.0



def _project(p: Sequence[float], a: Sequence[float], b: Sequence[float]) -> tuple[float, tuple[float, float]]:
    """The fraction along a→b of the point of the segment nearest ``p``, and that point."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2))
    return t, (a[0] + t * dx, a[1] + t * dy)


class PathFollower:
    """Pure pursuit along ``start`` → waypoints."""

    def __init__(self, start: Sequence[float], waypoints: Sequence[Sequence[float]],
                 settings: FollowSettings = FollowSettings(),
                 clearance: Callable[[float, float], float] | None = None) -> None:
        """:param clearance: the map's distance (m) from a point to the nearest wall, if known."""
        self.points = [(float(start[0]), float(start[1]))] + [(float(x), float(y)) for x, y in waypoints]
        self.settings = settings
        self.clearance = clearance
        #: Index of the segment the robot is on (points[i] → points[i + 1]).
        self.segment = 0

    @property
    def goal(self) -> tuple[float, float]:
        return self.points[-1]

    def remaining(self, pose: Sequence[float]) -> float:
        """The path's length (m) from the robot's nearest point on it to the goal."""
        i = self.segment
        _, near = _project(pose, self.points[i], self.points[i + 1])
        return math.dist(near, self.points[i + 1]) + sum(
            math.dist(a, b) for a, b in zip(self.points[i + 1:], self.points[i + 2:]))

    def _advance(self, pose: Sequence[float]) -> None:
        while self.segment < len(self.points) - 2:
            t, _ = _project(pose, self.points[self.segment], self.points[self.segment + 1])
            t_next, near_next = _project(pose, self.points[self.segment + 1], self.points[self.segment + 2])
            _, near = _project(pose, self.points[self.segment], self.points[self.segment + 1])
            if t >= 1.0 or math.dist(pose[:2], near_next) < math.dist(pose[:2], near) - 1e-9:
                self.segment += 1
            else:
                return

    def narrow(self, pose: Sequence[float]) -> bool:
        """Whether the map is narrow at the robot (see :class:`FollowSettings`)."""
        return self.clearance is not None and self.clearance(pose[0], pose[1]) < self.settings.narrow

    def target(self, pose: Sequence[float]) -> tuple[float, float]:
        """The point ``lookahead`` metres (``narrow_lookahead`` where narrow) along the path from
        the robot's nearest point on it."""
        self._advance(pose)
        i = self.segment
        _, here = _project(pose, self.points[i], self.points[i + 1])
        left = self.settings.narrow_lookahead if self.narrow(pose) else self.settings.lookahead
        a = here
        for b in self.points[i + 1:]:
            d = math.dist(a, b)
            if d >= left:
                return a[0] + (b[0] - a[0]) * left / d, a[1] + (b[1] - a[1]) * left / d
            left -= d
            a = b
        return self.goal

    def command(self, pose: Sequence[float], max_tv: float) -> tuple[float, float]:
        """(heading, speed) for the regulator: the heading towards :meth:`target`; no speed while
        turning to it, slower on the last metre."""
        tx, ty = self.target(pose)
        heading = math.atan2(ty - pose[1], tx - pose[0])
        error = abs(wrap(heading - pose[2]))
        narrow = self.narrow(pose)
        if error > (self.settings.narrow_turn_first if narrow else self.settings.turn_first):
            return heading, 0.0
        speed = max_tv * math.cos(error) * min(1.0, max(0.25, self.remaining(pose)))
        return heading, min(speed, self.settings.narrow_speed) if narrow else speed


class Progress:
    """Whether the remaining distance has fallen by ``progress`` metres within ``patience`` s."""

    def __init__(self, settings: FollowSettings = FollowSettings()) -> None:
        self.settings = settings
        self.best = math.inf
        self.since = math.nan

    def stuck(self, remaining: float, now: float) -> bool:
        if math.isnan(self.since) or remaining < self.best - self.settings.progress:
            self.best, self.since = remaining, now
            return False
        return now - self.since > self.settings.patience
