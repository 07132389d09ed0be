"""Ray following: Pluto's moveto without a map (Pluto 6.3), a pure function of scan, pose and goal.

Pluto 6.3: "The robot will not try to go through a wall but will see that the way is blocked and
look for the best open path (outdoors defined as 1.5 meters on each side of the robot).  It will then
follow that path (ray) checking both sides, right and left, as it goes to find any openings.  If it
finds an opening it will stop and decide if it is better to turn here (set a new ray) or to
continue."  And: "It will move the robot down the middle of the street"; near the goal it uses the
simple goto (element[2] = -2).

:func:`decide` is one such decision, called on every scan: near the goal with a clear street to
it, the avoid goto to the goal (``nearing``); with the goal behind the laser and no ray yet, a turn
in place towards it; otherwise the best open ray, kept unless a new one is better by
:attr:`RaySettings.switch`, its target moved to the middle of the street; with no open ray, a turn
towards the longest free beam.  docs/pluto-motion.md ("Ray following") gives each rule with its
settings and the element[3] codes it reports.

Before changing it: it keeps no state but the ray it follows (passed in and returned), so it is
tested without ROS; a street narrower than :attr:`RaySettings.half_width` (indoors) scores worse
but still counts, down to :attr:`RaySettings.min_half_width`.
"""

from __future__ import annotations

import dataclasses
import enum
import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .scan_points import wrap

__all__ = ['Action', 'RayDecision', 'RaySettings', 'ScanGeometry', 'decide', 'geometry_from_info', 'scan_points']

#: element[3] codes this module decides (Pluto 6.3).
SCANNING, FOLLOWING = 1, 3


class Action(enum.Enum):
    """What the motionModule does with a decision."""

    GOTO = 'goto'        # avoid goto (cmdFlags 32) to ``target``
    TURN = 'turn'        # turn in place to ``heading`` (the avoid's regulator, speed 0)


@dataclasses.dataclass(frozen=True)
class ScanGeometry:
    """Where the laser's beams point: beam ``i`` at ``first + i * step`` (rad, robot frame) from
    ``(mount_x, mount_y)``; readings at or past ``max_range`` or not positive are no echo."""

    first: float = -math.pi / 2
    step: float = math.pi / 360
    mount_x: float = 0.2
    mount_y: float = 0.0
    max_range: float = 80.0


@dataclasses.dataclass(frozen=True)
class RaySettings:
    """Distances in metres, angles in radians."""

    half_width: float = 1.5          # the seed's outdoor street: 1.5 m each side
    min_half_width: float = 0.45     # the narrowest street tried (robot radius + a margin)
    near: float = 2.5                # goal closer than this and in plain view: simple goto
    open_length: float = 3.0         # a ray is open if free this far (or to the goal)
    lookahead: float = 2.0           # the target's distance along the ray
    stop_short: float = 0.8          # a target stays this far before the ray's first obstacle
    step: float = math.radians(5.0)
    view: float = math.radians(85.0)  # rays within this of the heading (the laser sees +-90)
    behind: float = math.radians(100.0)
    switch: float = 0.5              # a new ray must leave this much less to the goal
    blocked: float = 3.0             # score added to a ray blocked before it gets nearest the goal
    narrow: float = 1.0              # score added per metre a street is narrower than half_width
    range_cap: float = 8.0           # free length counted at most this far


@dataclasses.dataclass(frozen=True)
class RayDecision:
    """One decision: ``action`` to ``target`` (goto) or ``heading`` (turn); ``ray`` the ray now
    followed (world direction, rad; pass it back as ``current``); ``status`` element[3] (1 scanning,
    3 following); ``nearing`` True when the goto goes to the goal itself (element[2] = -2)."""

    action: Action
    target: tuple[float, float]
    heading: float
    ray: float | None
    status: int
    nearing: bool = False


def geometry_from_info(info: Any) -> ScanGeometry:
    """The geometry a RangeFinder's info (``theta_offset``, ``theta_separation``, ``x_offset``,
    ``y_offset``, ``max_range``: WURDE 7.5's fan) says."""
    return ScanGeometry(float(info.theta_offset.get_value()), float(info.theta_separation.get_value()),
                        float(info.x_offset.get_value()), float(info.y_offset.get_value()),
                        float(info.max_range.get_value()))


def scan_points(ranges: ArrayLike, pose: Sequence[float], geometry: ScanGeometry = ScanGeometry()) -> NDArray:
    """The scan's echoes as world points ``(K, 2)``; ``pose`` the robot's (x, y, theta)."""
    r = np.asarray(ranges, dtype=float)
    angles = geometry.first + geometry.step * np.arange(len(r))
    ok = np.isfinite(r) & (r > 0.0) & (r < geometry.max_range)
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    lx = geometry.mount_x + r[ok] * np.cos(angles[ok])
    ly = geometry.mount_y + r[ok] * np.sin(angles[ok])
    return np.column_stack([x + c * lx - s * ly, y + s * lx + c * ly])



def _free_length(rel: NDArray, phi: float, half_width: float, cap: float) -> float:
    """How far (m) a street of ``half_width`` along ``phi`` is free of the points ``rel``."""
    if len(rel) == 0:
        return cap
    f = rel[:, 0] * math.cos(phi) + rel[:, 1] * math.sin(phi)
    lateral = -rel[:, 0] * math.sin(phi) + rel[:, 1] * math.cos(phi)
    hit = (f > 0.0) & (np.abs(lateral) < half_width)
    return min(cap, float(f[hit].min())) if hit.any() else cap


def _middle(rel: NDArray, phi: float, at: float, half_width: float, cap: float) -> float:
    """Sideways shift (m, left positive) to the middle of the street around ``at`` m along
    ``phi``: half the difference of the free space left and right (each counted to ``cap``)."""
    if len(rel) == 0:
        return 0.0
    f = rel[:, 0] * math.cos(phi) + rel[:, 1] * math.sin(phi)
    lateral = -rel[:, 0] * math.sin(phi) + rel[:, 1] * math.cos(phi)
    window = (f > max(0.0, at - 1.0)) & (f < at + 1.0)
    left = lateral[window & (lateral > 0)]
    right = -lateral[window & (lateral < 0)]
    space_left = min(cap, float(left.min())) if len(left) else cap
    space_right = min(cap, float(right.min())) if len(right) else cap
    return float(np.clip((space_left - space_right) / 2.0, -half_width, half_width))


def decide(points: ArrayLike, pose: Sequence[float], goal: Sequence[float], current: float | None = None,
           settings: RaySettings = RaySettings()) -> RayDecision:
    """The next step of ray following.

    :param points: echoes in the world frame (:func:`scan_points`): the last few scans together,
        since the laser (180 degrees ahead) does not see the robot's flanks when it turns.
    :param pose: the robot's (x, y, theta).
    :param goal: the moveto point (x, y).
    :param current: the ray being followed (its direction), None at the start.
    """
    s = settings
    x, y, theta = (float(v) for v in pose)
    rel = np.asarray(points, dtype=float).reshape(-1, 2) - (x, y)
    dx, dy = goal[0] - x, goal[1] - y
    distance = math.hypot(dx, dy)
    bearing = math.atan2(dy, dx)
    goal_t = (float(goal[0]), float(goal[1]))
    if distance < s.near and abs(wrap(bearing - theta)) <= s.view \
            and _free_length(rel, bearing, s.min_half_width, s.range_cap) >= distance:
        return RayDecision(Action.GOTO, goal_t, bearing, bearing, FOLLOWING, nearing=True)
    if current is None and abs(wrap(bearing - theta)) > s.behind:
        return RayDecision(Action.TURN, (x, y), bearing, None, SCANNING)
    best: tuple[float, float, float, float] | None = None      # (score, ray, free length, width)
    kept: tuple[float, float, float, float] | None = None
    for width in _widths(s):
        for phi in _rays(theta, current, s):
            free = _free_length(rel, phi, width, s.range_cap)
            if free < min(s.open_length, distance):
                continue
            candidate = (_score(free, phi, dx, dy, s) + s.narrow * (s.half_width - width), phi, free, width)
            if best is None or candidate[0] < best[0]:
                best = candidate
            if phi == current and (kept is None or candidate[0] < kept[0]):
                kept = candidate
    if best is None:                                             # boxed in: look elsewhere
        return RayDecision(Action.TURN, (x, y), wrap(theta + _open_side(rel, theta, s)), None, SCANNING)
    if kept is not None and kept[0] <= best[0] + s.switch:
        chosen, status = kept, FOLLOWING
    else:
        chosen, status = best, SCANNING
    _, phi, free, width = chosen
    ahead = max(0.3, min(s.lookahead, free - s.stop_short, distance))
    shift = _middle(rel, phi, ahead, width, s.range_cap)
    target = (x + ahead * math.cos(phi) - shift * math.sin(phi), y + ahead * math.sin(phi) + shift * math.cos(phi))
    to_target = math.atan2(target[1] - y, target[0] - x)
    if _free_length(rel, to_target, s.min_half_width, s.range_cap) < math.hypot(ahead, shift) + s.stop_short:
        target = (x + ahead * math.cos(phi), y + ahead * math.sin(phi))     # the shift would graze
    return RayDecision(Action.GOTO, target, phi, phi, status)


def _widths(s: RaySettings) -> list[float]:
    """The street half-widths tried: the seed's 1.5 m down to the narrowest, 0.35 m apart."""
    widths = [s.half_width]
    while widths[-1] - 0.35 > s.min_half_width:
        widths.append(widths[-1] - 0.35)
    return widths + [s.min_half_width]


def _rays(theta: float, current: float | None, s: RaySettings) -> list[float]:
    """Directions within the laser's view, every ``s.step``; the current ray itself when in view."""
    rays = [wrap(theta + k * s.step) for k in range(-int(s.view / s.step), int(s.view / s.step) + 1)]
    if current is not None and abs(wrap(current - theta)) <= s.view:
        rays = [phi for phi in rays if abs(wrap(phi - current)) >= s.step / 2] + [current]
    return rays


def _score(free: float, phi: float, dx: float, dy: float, s: RaySettings) -> float:
    """Distance (m) left to the goal after driving along ``phi`` as far as it goes towards the
    goal, plus :attr:`RaySettings.blocked` when an obstacle on the ray comes before the point
    nearest the goal (a dead end is worse than a detour)."""
    along_goal = dx * math.cos(phi) + dy * math.sin(phi)
    along = max(0.0, min(free - s.stop_short, along_goal))
    left = math.hypot(dx - along * math.cos(phi), dy - along * math.sin(phi))
    return left + (s.blocked if free < min(along_goal, s.range_cap) else 0.0)


def _open_side(rel: NDArray, theta: float, s: RaySettings) -> float:
    """Turn (rad) towards the side whose edge of the view is more open: +-90 degrees."""
    left = _free_length(rel, theta + s.view, s.min_half_width, s.range_cap)
    right = _free_length(rel, theta - s.view, s.min_half_width, s.range_cap)
    return math.pi / 2 if left >= right else -math.pi / 2
