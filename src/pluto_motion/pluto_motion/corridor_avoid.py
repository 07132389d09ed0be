"""Choosing a free direction from a laser scan: the avoidance of the LaserAvoider (WURDE 7.7).

The guide gives no algorithm ("a laser rangefinder-based obstacle avoidance algorithm"), so this
is a plain and checkable one.  The robot is a disc; for each candidate heading the length it can
drive straight before the disc, grown by the safety distance, touches a scan point is computed
exactly (a swept disc, not a ray).  Of the headings free for the whole look-ahead (or up to the
goal, when nearer) the one closest to the goal's bearing wins; when none is, of those that leave at
least ``min_step``; the step is the free length, capped at the look-ahead and the goal's distance.
Nothing free is *blocked*.  The side of the bearing a way round went by is kept unless the other
side is better by ``side_bias``.  A goal outside the ``fan`` of candidate headings is turned to on
the spot first (a disc turns safely), unless the robot is going round something (a side kept): then
the free heading in view nearest the goal is taken, which turns the robot towards the goal through
headings it sees free (``fan_margin``).

A point already within the safety distance (a late command or scan let the robot come nearer than
it would have stopped) blocks only the headings that bring the robot nearer to it; moving away is
free.  When every heading in view brings it nearer, the robot turns on the spot until the nearest
point is nearly beside it (:func:`choose`), instead of standing blocked for good: a loaded machine's
late scans once left the guide's avoider 0.45 m from a box, blocked until the test gave up.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .scan_points import Beams

__all__ = ['ESCAPE_ANGLE', 'AvoidSettings', 'Choice', 'choose', 'clearance', 'free_lengths', 'navigator_move',
           'scan_to_points', 'turn_step']

#: A robot too near a point turns until the point is this far (rad) off its heading: 20 degrees
#: short of beside it, so that a goal beyond the point stays inside the 80-degree fan.
ESCAPE_ANGLE = math.radians(70)


@dataclasses.dataclass(frozen=True)
class AvoidSettings:
    """Geometry of the avoider (m, rad)."""

    radius: float = 0.35
    safety: float = 0.15
    lookahead: float = 1.5
    min_step: float = 0.3
    #: Candidate headings span +-fan around straight ahead (the laser sees +-90 degrees).
    fan: float = math.radians(80)
    step: float = math.radians(4)
    #: A goal nearer than this is reached.
    reach: float = 0.15
    #: Once a side of the goal's bearing is chosen, a heading on the other side costs this much
    #: more (rad): the way round an obstacle is kept unless the other way is clearly shorter.
    side_bias: float = math.radians(30)
    #: While going round something (a side kept), a goal out of view is turned to only when it is
    #: this much beyond the fan (rad); by default never, as a bearing is at most pi.  At the fan's
    #: edge (a margin of 0) the way round and the turn to the goal undid each other, each before a
    #: mover that turns first had faced it; with a margin of 30 degrees they did the same at the
    #: margin: a goal behind and a way round away from it held the robot turning back and forth
    #: where it stood (``bench/guide_avoider.py``: 2 of 120 cluttered rooms not reached, and at
    #: 9600 baud a standstill long enough for the scan memory to forget a box, which was touched).
    fan_margin: float = math.pi


@dataclasses.dataclass(frozen=True)
class Choice:
    """What to do next: drive ``length`` m along ``heading`` (robot frame), or turn on the spot by
    ``heading`` when ``rotate``; ``blocked`` when no heading is free.  ``closest`` is the nearest
    scan point's distance from the robot's edge (m)."""

    heading: float
    length: float
    rotate: bool
    blocked: bool
    reached: bool
    closest: float
    #: The side of the goal's bearing the move goes round by: 1 left, -1 right, 0 straight at it
    #: (or no move); the next :func:`choose` is given it.
    side: int = 0


def scan_to_points(ranges: ArrayLike, first: float, separation: float, *, x_offset: float = 0.0,
                   y_offset: float = 0.0, max_range: float = math.inf) -> NDArray:
    """The valid readings (finite, 0 < r < max_range) as ``(N, 2)`` points in the robot frame, for a
    laser at (x_offset, y_offset) whose beam ``i`` points at ``first + i * separation``."""
    r = np.asarray(ranges, dtype=float)
    r = np.where(r < (max_range if max_range > 0 else math.inf), r, np.nan)
    return Beams.fan(len(r), first=first, step=separation, x=x_offset, y=y_offset).points(r)


def free_lengths(points: NDArray, headings: NDArray, half_width: float, limit: float) -> NDArray:
    """For each heading, how far (m, at most ``limit``) a disc of radius ``half_width`` at the
    origin can move along it before touching a point.  A point already inside the disc gives 0 for
    a heading that brings the disc nearer to it, and does not limit one that moves away from it (the
    distance to it only grows)."""
    if len(points) == 0:
        return np.full(len(headings), float(limit))
    c, s = np.cos(headings)[:, None], np.sin(headings)[:, None]
    u = points[:, 0] * c + points[:, 1] * s             # along the heading
    v = -points[:, 0] * s + points[:, 1] * c            # across it
    across = half_width ** 2 - v ** 2
    inside = across > 0
    reach = np.where(inside, u - np.sqrt(np.where(inside, across, 0.0)), np.inf)
    # A point the disc has fully passed (behind its back edge) never touches it.
    ahead = inside & (u + np.sqrt(np.where(inside, across, 0.0)) > 0)
    reach = np.where(ahead, reach, np.inf)
    already = u ** 2 + v ** 2 < half_width ** 2
    reach = np.where(already, np.where(u > 0, 0.0, np.inf), reach)
    return np.clip(reach.min(axis=1), 0.0, limit)


def clearance(points: NDArray, radius: float) -> float:
    """The nearest point's distance from the edge of a disc of ``radius`` at the origin (m)."""
    return float(np.hypot(points[:, 0], points[:, 1]).min() - radius) if len(points) else math.inf


def choose(points: NDArray, goal: tuple[float, float], settings: AvoidSettings = AvoidSettings(),
           side: int = 0, heading: float = 0.0) -> Choice:
    """The next move towards ``goal`` (robot frame, m) among the scan ``points`` (robot frame);
    ``side`` is the last choice's :attr:`Choice.side`; ``heading`` the robot's in the odometry
    frame.

    The side is kept: headings on the other side of the goal's bearing cost
    :attr:`AvoidSettings.side_bias` more.  Without it, a goal straight beyond an obstacle has two
    ways round of nearly the same cost, and which is nearer the bearing on the heading grid changes
    as the robot turns: the robot turned left and right in turn for good (a kinematic simulation
    of the guide's avoider and mover, goal 4 m beyond the middle of a 0.6 m box).  With a side
    kept, a goal out of view is not turned to (:attr:`AvoidSettings.fan_margin`).

    The candidate headings are fixed in the odometry frame (multiples of
    :attr:`AvoidSettings.step` there), so that a robot turning on the spot weighs the same
    directions.  With a grid fixed to the robot, a narrow way free for the whole look-ahead was
    on the grid at one heading and between two of its headings 2 degrees on: the choice went from
    it to a way nearer the goal free for part of the look-ahead and back, each turning the robot a
    little towards itself, and the robot turned back and forth where it stood
    (``bench/guide_avoider.py``, 2 of 120 rooms at 38400 baud)."""
    half_width = settings.radius + settings.safety
    closest = clearance(points, settings.radius)
    distance = math.hypot(*goal)
    bearing = math.atan2(goal[1], goal[0])
    if distance <= settings.reach:
        return Choice(0.0, 0.0, False, False, True, closest)
    if abs(bearing) > settings.fan + (settings.fan_margin if side else 0.0):
        return Choice(bearing, 0.0, True, False, False, closest, side)
    want = min(distance, settings.lookahead)
    first = math.ceil((heading - settings.fan) / settings.step - 1e-9) * settings.step - heading
    grid = np.arange(first, settings.fan + 1e-9, settings.step)
    headings = np.concatenate(([bearing], grid))
    free = free_lengths(points, headings, half_width, want)
    clear = free >= want - 1e-9                          # the whole look-ahead is free
    feasible = clear if clear.any() else free >= min(settings.min_step, want) - 1e-9
    if not feasible.any():
        if len(points) and closest < settings.safety:
            turn, side = _turn_away(points, bearing, side)
            return Choice(turn, 0.0, True, False, False, closest, side)
        return Choice(0.0, 0.0, False, True, False, closest, side)
    offset = headings - bearing
    cost = np.abs(offset) + np.where(feasible, 0.0, np.inf)
    if side:
        cost = cost + np.where(offset * side < -1e-9, settings.side_bias, 0.0)
    best = int(np.argmin(cost))
    chosen = 0 if abs(offset[best]) < 1e-9 else (1 if offset[best] > 0 else -1)
    return Choice(float(headings[best]), float(free[best]), False, False, False, closest, chosen)


def _turn_away(points: NDArray, bearing: float, side: int) -> tuple[float, int]:
    """The turn on the spot (rad) that puts the nearest point :data:`ESCAPE_ANGLE` off the robot's
    side, and the side of the point it goes round by: ``side`` when one is kept, else the side that
    turns towards the goal's ``bearing``: headings that move away from the point are then in view,
    and the goal is not so far behind that it would be turned to straight back."""
    nearest = points[int(np.argmin(np.hypot(points[:, 0], points[:, 1])))]
    towards = math.atan2(nearest[1], nearest[0])
    if not side:
        side = 1 if math.remainder(bearing - towards, math.tau) >= 0 else -1
    return math.remainder(towards + side * ESCAPE_ANGLE, math.tau), side


def turn_step(points: NDArray, turn: float, half_width: float, length: float,
              resolution: float = AvoidSettings.step) -> float | None:
    """The heading (robot frame) of a short step of ``length`` m that stands in for a turn on the
    spot by ``turn``, for a mover that cannot turn on the spot (a Navigator goes to points; the
    VectorMover turns to face a point before it drives there), or None when no step is free.

    The step goes along ``turn`` when the disc is free along it for the whole ``length``
    (:func:`free_lengths`), else along the free heading nearest to it (``resolution`` apart,
    the turn's own direction first).  A step along the escape turn of :func:`choose` itself would
    not do: it keeps the nearest point :data:`ESCAPE_ANGLE` off the heading, so that each step
    brings the robot ``length`` x cos 70 degrees nearer to it (a test saw the guide's chapter-1
    avoider creep so into a box until the bumper stopped the base, for good); along the nearest
    free heading the point is beside or behind the step, which moves along it or away from it.

    The escape turn and a turn back to a goal just out of view undid each other before the
    mover, which turns first, had faced either: the fan margin of :func:`choose` ends that."""
    if len(points) == 0:
        return turn
    side = 1.0 if turn >= 0 else -1.0
    k = np.arange(1, int(math.pi / resolution) + 1)
    offsets = np.concatenate(([0.0], np.stack([side * k, -side * k], axis=1).ravel() * resolution))
    headings = np.remainder(turn + offsets + math.pi, math.tau) - math.pi
    free = free_lengths(points, headings, half_width, length) >= length - 1e-9
    return float(headings[int(np.argmax(free))]) if free.any() else None


def navigator_move(points: NDArray, length: float, heading: float, half_width: float,
                   step: float) -> tuple[float, float] | None:
    """The move ``(length, heading)`` for a mover that goes to points only: a turn on the spot
    (``length`` 0) becomes a step of ``step`` m along :func:`turn_step`'s heading; None when no
    step is free (the robot is to stop)."""
    if length >= 1e-3 or heading == 0.0:
        return length, heading
    free = turn_step(points, heading, half_width, step)
    return None if free is None else (step, free)
