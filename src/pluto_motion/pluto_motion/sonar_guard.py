"""Sonar collision protection of the driveModule (Pluto 6.1: "When the sonar ... detects an obstacle it
slows the robot to a safe speed, eventually stoping the robot if needed"; element[0] 3 front, 4 back,
5 sides).

The ring is split by each sonar's bearing: front within 45 degrees of straight ahead, back within 45
degrees of straight behind, the rest are the sides; the code says which group slowed the robot.

Driving forward the front sonars limit the speed, backward the back ones, by what lies *in the
way*: an echo at range r may come from anywhere on the arc of the sonar's cone (its half angle) at
r, and only the arc's points inside the corridor the robot's round footprint sweeps (radius plus
``margin``) count, by their distance ahead of the footprint's edge.  So walls beside the robot —
the jambs of a 0.9 m door — slow it at most, and do not stop it, as a bearing-only rule did (a sonar
45 degrees off the heading sees a door's jamb 0.3 m away).  The allowed speed falls linearly from
the full speed at ``slow`` metres of free way to zero at ``stop``; a slowed speed under ``creep`` is
a stop.  The side sonars slow the robot from ``side_slow`` and stop it at ``side_stop`` of the
sensor (touching), whatever the direction.  Readings that are not finite or not positive are no echo.
Without the ring's positions (:meth:`SonarGuard.set_bearings` alone) the sensors are taken at the
robot's centre.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

__all__ = ['BACK', 'FRONT', 'SIDES', 'SonarGuard', 'SonarLimits', 'ring_layout']

FRONT, BACK, SIDES = 3, 4, 5
_QUARTER = math.pi / 4


@dataclasses.dataclass(frozen=True)
class SonarLimits:
    """Distances (m) at which the robot starts slowing and stops (front and back: free way ahead of
    the footprint; sides: range from the sensor)."""

    #: Free way (m) ahead of the footprint's edge at which the robot stops, and starts slowing.
    stop: float = 0.1
    slow: float = 0.9
    side_stop: float = 0.05
    side_slow: float = 0.3
    #: The footprint: the robot's radius (m) and a margin added to it for the swept corridor.
    radius: float = 0.35
    margin: float = 0.05
    #: m/s: a slowed speed below this is a stop (else the robot would creep towards the stop
    #: distance for ever, its speed shrinking with the gap).
    creep: float = 0.05


def _group(bearing: float) -> int:
    a = math.atan2(math.sin(bearing), math.cos(bearing))
    if abs(a) <= _QUARTER:
        return FRONT
    if abs(a) >= math.pi - _QUARTER:
        return BACK
    return SIDES


def ring_layout(count: int, first: float, step: float, x0: float, y0: float) -> list[tuple[float, float, float]]:
    """(x, y, bearing) of ``count`` sonars laid out uniformly (RangeFinder info without positions):
    the first at (x0, y0) with bearing ``first``, each next one turned by ``step`` about the centre."""
    layout = []
    for i in range(count):
        a = i * step
        layout.append((x0 * math.cos(a) - y0 * math.sin(a), x0 * math.sin(a) + y0 * math.cos(a), first + a))
    return layout


def _fraction(distance: float, stop: float, slow: float) -> float:
    if distance <= stop:
        return 0.0
    if distance >= slow:
        return 1.0
    return (distance - stop) / (slow - stop)


class SonarGuard:
    """The speed the sonar allows; :meth:`set_layout` (or :meth:`set_bearings`) once the ring's info
    is known."""

    #: Points sampled across a cone's arc (odd: the axis is one of them).
    ARC_SAMPLES = 5

    def __init__(self, limits: SonarLimits = SonarLimits()) -> None:
        self.limits = limits
        self.groups: list[int] = []
        self.sensors: list[tuple[float, float, float]] = []
        self.half_angle = 0.0

    def set_bearings(self, bearings: Sequence[float]) -> None:
        """The bearing of each sonar in the robot frame (rad, 0 straight ahead, counter-clockwise),
        the sensors at the robot's centre with no cone."""
        self.set_layout([(0.0, 0.0, b) for b in bearings], 0.0)

    def set_layout(self, sensors: Sequence[tuple[float, float, float]], half_angle: float) -> None:
        """Each sonar's (x, y, bearing) in the robot frame (m, rad) and the cones' half angle."""
        self.sensors = [(float(x), float(y), float(b)) for x, y, b in sensors]
        self.groups = [_group(b) for _, _, b in self.sensors]
        self.half_angle = abs(float(half_angle)) if math.isfinite(half_angle) else 0.0

    @property
    def ready(self) -> bool:
        return bool(self.groups)

    def free_way(self, sensor: tuple[float, float, float], r: float, forward: bool) -> float:
        """How far (m) the footprint can go straight (ahead, or back) before the nearest point of the
        echo's arc; infinite when the arc is outside the swept corridor."""
        x0, y0, bearing = sensor
        width = self.limits.radius + self.limits.margin
        n = self.ARC_SAMPLES
        free = math.inf
        for k in range(n):
            a = bearing + self.half_angle * (2 * k / (n - 1) - 1) if n > 1 else bearing
            x, y = x0 + r * math.cos(a), y0 + r * math.sin(a)
            along = x if forward else -x
            if abs(y) < width and along > -width:
                free = min(free, along - math.sqrt(width * width - y * y))
        return max(free, 0.0)

    def limit(self, tv: float, ranges: Sequence[float], wanted: float | None = None) -> tuple[float, int]:
        """``tv`` slowed for the nearest obstacle in the way and the code of the group that slowed
        it (0 when nothing did).  ``wanted`` is the speed asked for (default ``tv``): the allowed
        speed is that times the fraction, a stop when under ``creep``, and ``tv`` (which may still
        be ramping up) is cut to it.  Rotation in place is never limited: the footprint is round."""
        wanted = tv if wanted is None else wanted
        if tv == 0.0 or not self.groups:
            return tv, 0
        forward = tv > 0
        ahead = FRONT if forward else BACK
        best, code = 1.0, 0
        for sensor, group, r in zip(self.sensors, self.groups, ranges):
            if not math.isfinite(r) or r <= 0.0:
                continue
            if group == ahead:
                f = _fraction(self.free_way(sensor, r, forward), self.limits.stop, self.limits.slow)
            elif group == SIDES:
                f = _fraction(r, self.limits.side_stop, self.limits.side_slow)
            else:
                continue
            if f < best:
                best, code = f, group
        if best >= 1.0:
            return tv, 0
        cap = abs(wanted) * best
        if cap < self.limits.creep:
            cap = 0.0
        return math.copysign(min(abs(tv), cap), tv), code
