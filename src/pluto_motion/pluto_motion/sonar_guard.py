"""Sonar collision protection of the driveModule (Pluto 6.1: "When the sonar ... detects an obstacle it
slows the robot to a safe speed, eventually stoping the robot if needed"; element[0] 3 front, 4 back,
5 sides).

The ring is split by each sonar's bearing: front within 45 degrees of straight ahead, back within 45
degrees of straight behind, the rest are the sides.  Driving forward the front sonars limit the
speed, backward the back ones; the side sonars limit both directions (at shorter distances, since a
round robot passing a wall is not driving into it).  The allowed speed falls linearly from the full
speed at ``slow`` metres to zero at ``stop`` metres (ranges as the sonars report them, from the
sensor); a slowed speed under ``creep`` is a stop.  Readings that are not finite or not positive are no echo and ignored.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

__all__ = ['BACK', 'FRONT', 'SIDES', 'SonarGuard', 'SonarLimits']

FRONT, BACK, SIDES = 3, 4, 5
_QUARTER = math.pi / 4


@dataclasses.dataclass(frozen=True)
class SonarLimits:
    """Distances (m, from the sensor) at which each group starts slowing and stops the robot."""

    stop: float = 0.3
    slow: float = 1.2
    side_stop: float = 0.05
    side_slow: float = 0.3
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


def _fraction(distance: float, stop: float, slow: float) -> float:
    if distance <= stop:
        return 0.0
    if distance >= slow:
        return 1.0
    return (distance - stop) / (slow - stop)


class SonarGuard:
    """The speed the sonar allows; :meth:`set_bearings` once the ring's info is known."""

    def __init__(self, limits: SonarLimits = SonarLimits()) -> None:
        self.limits = limits
        self.groups: list[int] = []

    def set_bearings(self, bearings: Sequence[float]) -> None:
        """The bearing of each sonar in the robot frame (rad, 0 straight ahead, counter-clockwise)."""
        self.groups = [_group(b) for b in bearings]

    @property
    def ready(self) -> bool:
        return bool(self.groups)

    def limit(self, tv: float, ranges: Sequence[float], wanted: float | None = None) -> tuple[float, int]:
        """``tv`` slowed for the nearest obstacle and the code of the group that slowed it (0 when
        nothing did).  ``wanted`` is the speed asked for (default ``tv``): the allowed speed is
        that times the group's fraction, a stop when under ``creep``, and ``tv`` (which may still
        be ramping up) is cut to it.  Rotation in place is never limited: the footprint is round."""
        wanted = tv if wanted is None else wanted
        if tv == 0.0 or not self.groups:
            return tv, 0
        ahead = FRONT if tv > 0 else BACK
        best, code = 1.0, 0
        for group, r in zip(self.groups, ranges):
            if not math.isfinite(r) or r <= 0.0:
                continue
            if group == ahead:
                f = _fraction(r, self.limits.stop, self.limits.slow)
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
