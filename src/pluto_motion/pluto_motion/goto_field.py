"""The avoid goto's vector summation (Pluto 6.2: "The goto command ... will try to go around obstacles
using a vector summation rule.  It reacts to near (<3m) obstacles using the laser and sonar.  It
then will steer around the obstacle.").

Per step, in the robot frame (x forward, y left), :func:`goto_step` sums an attraction to the goal
(times the command's force[0]) and a repulsion from the nearest laser or sonar point per bearing
bin within :attr:`FieldSettings.reach`, adds a sideways push round an obstacle in the way, and
turns the sum into a heading and a speed slowed near obstacles and the goal.
:class:`GotoProgress` tells when the goal is reached or the goto is stuck.  docs/pluto-motion.md
("The avoid goto") gives each step's rule and the settings it uses.

Before changing it:

- Each bin keeps only its nearest point, so a wall pushes as hard whether 361 laser beams or one
  sonar see it, and the two sensors do not add up.
- A point beside the way to the goal pushes only sideways, and one beyond the goal not at all:
  walls and door jambs hold the robot in the middle, not back, nor short of a goal by a wall.
- The side the robot steers round an obstacle is kept until nothing blocks.  The repulsion's lean
  turns with the robot (the laser sees only its front half) and with late scans and an uneven
  loop it flips, and a robot that follows the flip circles until the goto is stuck.
- The heading leads the robot by at most ``max_rv / heading_gain``, so the drive's regulator
  never turns faster than the maximum angular velocity.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .laser_guard import free_distance
from .scan_points import wrap

__all__ = ['FieldSettings', 'GotoProgress', 'GotoStep', 'nearest_per_bin', 'goto_step']


@dataclasses.dataclass(frozen=True)
class FieldSettings:
    """Constants of the vector summation (metres, seconds, radians)."""

    radius: float = 0.35           # the robot's footprint (config/pluto: 0.35 m)
    reach: float = 3.0             # obstacles nearer than this (centre) push (Pluto 6.2: "<3m")
    bins: int = 72                 # bearing bins round the robot (5 degrees)
    gain: float = 1.2              # repulsion per rad of bin width and 1/m of gap
    min_gap: float = 0.05          # gaps below this count as this (no infinite push)
    tangent_gain: float = 1.0      # steering round: sideways push per unit of blocking push
    tie: float = 0.25              # a sideways lean below this share of the blocking push is none
    way_reach: float = 1.5         # steering round only for an obstacle this near in the goal's way ...
    way_margin: float = 0.1        # ... of the footprint widened by this on each side
    goal_slow: float = 1.0         # slow down within this distance of the goal
    clear_stop: float = 0.1        # free distance along the heading at which the speed is 0 ...
    clear_slow: float = 1.0        # ... and from which it is full
    near_slow: float = 0.6         # an obstacle nearer than this (any direction) slows the robot ...
    near_floor: float = 0.3        # ... down to this share of the speed (0 at too_close)
    heading_gain: float = 1.5      # the drive's regulator gain (rad/s per rad)
    reach_goal: float = 0.15       # the goal is reached within this distance
    progress: float = 0.2          # the distance to the goal must shrink by this ...
    stuck_s: float = 10.0          # ... within this time, or the goto is stuck
    too_close: float = 0.03        # an obstacle this near the footprint's edge: stuck at once


@dataclasses.dataclass(frozen=True)
class GotoStep:
    """One step's output: the heading (rad, the pose's frame) and speed (m/s) for the drive's
    regulator, the distance to the goal, the nearest gap to any obstacle and the side chosen."""

    heading: float
    speed: float
    distance: float
    nearest_gap: float
    side: int
    reached: bool


def nearest_per_bin(points: np.ndarray, bins: int, reach: float,
                    cones: np.ndarray | None = None) -> np.ndarray:
    """For each of ``bins`` bearing bins round the origin, the distance of the nearest point in it
    nearer than ``reach`` (inf where none).  ``cones`` (N,) half widths (rad): a point also fills the
    bins within its half width (a sonar's cone)."""
    nearest = np.full(bins, np.inf)
    if len(points) == 0:
        return nearest
    d = np.hypot(points[:, 0], points[:, 1])
    near = d < reach
    if not np.any(near):
        return nearest
    width = 2 * math.pi / bins
    bearing = np.arctan2(points[near, 1], points[near, 0])
    d = d[near]
    if cones is None:
        index = np.floor((bearing + math.pi) / width).astype(int) % bins
        np.minimum.at(nearest, index, d)
        return nearest
    half = np.ceil(cones[near] / width).astype(int)
    centre = np.floor((bearing + math.pi) / width).astype(int)
    for k in range(-int(half.max()), int(half.max()) + 1):
        use = np.abs(k) <= half
        np.minimum.at(nearest, (centre[use] + k) % bins, d[use])
    return nearest


def _ramp(value: float, low: float, high: float) -> float:
    """0 at ``low`` and below, 1 at ``high`` and above, linear between."""
    return 1.0 if value >= high else max(0.0, (value - low) / (high - low))


def _repulsion(nearest: np.ndarray, to_goal: np.ndarray, distance: float, s: FieldSettings) -> np.ndarray:
    bins = len(nearest)
    width = 2 * math.pi / bins
    centres = -math.pi + width * (np.arange(bins) + 0.5)
    use = np.isfinite(nearest)
    if not np.any(use):
        return np.zeros(2)
    d, c = nearest[use], centres[use]
    gap = np.maximum(d - s.radius, s.min_gap)
    push = np.maximum(s.gain * width * (1.0 / gap - 1.0 / (s.reach - s.radius)), 0.0)
    away = -np.column_stack((np.cos(c), np.sin(c))) * push[:, None]
    # Beside the way to the goal: only the sideways part (a corridor's walls do not hold it back).
    along = d * (np.cos(c) * to_goal[0] + np.sin(c) * to_goal[1])
    across = d * (-np.cos(c) * to_goal[1] + np.sin(c) * to_goal[0])
    beside = (np.abs(across) >= s.radius + s.way_margin) | (along <= 0.0)
    away[beside] -= np.outer(away[beside] @ to_goal, to_goal)
    # Beyond the goal, where the footprint never comes, nothing pushes: such a wall's push balanced
    # the goal's pull short of a goal near it, a potential field's trap (0.4-0.56 m short on a
    # generated map), and its sideways part only bent the last metre.
    away[along >= distance + s.radius] = 0.0
    return away.sum(axis=0)


def goto_step(pose: tuple[float, float, float], goal: tuple[float, float], points: np.ndarray,
              *, max_tv: float, max_rv: float, strength: float = 1.0, side: int = 0,
              cones: np.ndarray | None = None, settings: FieldSettings = FieldSettings()) -> GotoStep:
    """One step of the goto from ``pose`` (x, y, theta) to ``goal`` with obstacle ``points`` ((N, 2),
    robot frame; ``cones`` their half widths, None: all 0).  ``side`` is the side chosen before (+1
    left, -1 right, 0 none)."""
    s = settings
    x, y, theta = pose
    dx, dy = goal[0] - x, goal[1] - y
    distance = math.hypot(dx, dy)
    nearest = nearest_per_bin(points, s.bins, s.reach, cones)
    nearest_gap = float(np.min(nearest)) - s.radius if np.any(np.isfinite(nearest)) else math.inf
    if distance <= s.reach_goal:
        return GotoStep(theta, 0.0, distance, nearest_gap, 0, True)
    c, sn = math.cos(theta), math.sin(theta)
    to_goal = np.array([c * dx + sn * dy, -sn * dx + c * dy]) / distance
    push = _repulsion(nearest, to_goal, distance, s)
    bearing = math.atan2(to_goal[1], to_goal[0])
    in_way = free_distance(points, s.radius, s.way_margin, bearing) if len(points) else math.inf
    block = max(0.0, -float(push @ to_goal)) if in_way < min(distance, s.way_reach) else 0.0
    normal = np.array([-to_goal[1], to_goal[0]])
    lean = float(push @ normal)
    if block < 1e-3:
        side = 0
    elif side == 0:
        side = 1 if lean >= s.tie * block else -1 if lean <= -s.tie * block else 1
    total = strength * to_goal + push + side * block * s.tangent_gain * normal
    turn = math.atan2(total[1], total[0]) if np.any(total) else 0.0
    lead = max(-max_rv / s.heading_gain, min(max_rv / s.heading_gain, turn))
    gap = min(free_distance(points, s.radius, 0.0, turn), free_distance(points, s.radius, 0.0, 0.0))
    near = 0.0 if nearest_gap <= s.too_close else s.near_floor + (1 - s.near_floor) * _ramp(
        nearest_gap, s.too_close, s.near_slow)
    clear = _ramp(gap, s.clear_stop, s.clear_slow) * near
    speed = max_tv * min(1.0, distance / s.goal_slow) * clear * max(0.0, math.cos(turn))
    return GotoStep(wrap(theta + lead), speed, distance, nearest_gap, side, False)


class GotoProgress:
    """Whether a goto is stuck: no progress of ``progress`` m in ``stuck_s`` s, or too close."""

    def __init__(self, settings: FieldSettings = FieldSettings()) -> None:
        self.settings = settings
        self.best = math.inf
        self.since = 0.0

    def start(self, now: float) -> None:
        self.best, self.since = math.inf, now

    def stuck(self, step: GotoStep, now: float) -> str | None:
        """Why the goto is stuck after ``step``, or None when it is not."""
        s = self.settings
        if step.distance < self.best - s.progress:
            self.best, self.since = step.distance, now
        if step.nearest_gap < s.too_close:
            return f'an obstacle {step.nearest_gap:.3f} m from the footprint'
        if now - self.since > s.stuck_s:
            return f'no {s.progress} m of progress in {s.stuck_s} s ({step.distance:.2f} m to go)'
        return None
