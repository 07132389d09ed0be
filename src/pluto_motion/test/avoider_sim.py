"""A kinematic simulation of chapter 1's pair (guide 1.1.5): the LaserAvoider's choice
(:func:`pluto_motion.corridor_avoid.choose`, a turn driven as a step for a Navigator) feeding the
VectorMover's control law (:class:`pluto_motion.vector_follower.VectorFollower`, which turns on the
spot before it drives), on a round robot among wall segments.  No ROS; deterministic for a seed.

The avoider decides every ``dt`` and sends the mover a new point each time, as the real pair does
at the avoider's 20 Hz loop.  By default it has a fresh scan every time; with ``scan_period`` and
``latency`` a scan is taken every period and reaches the avoider ``latency`` after its centre time
(the SICK at 38400 baud: 0.19 s and 0.2 s), and the avoider places it at the pose of that time
(``stamped``, as the LaserAvoider does) or at the robot's pose when it looks.  Other message
delays it cannot show."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from goto_sim import LASER, Run, Segment, clearance, raycast
from pluto_motion.corridor_avoid import AvoidSettings, choose, navigator_move
from pluto_motion.laser_avoider import DEFAULT_RV, DEFAULT_TV, NAV_TURN_STEP
from pluto_motion.scan_memory import LaserView, ScanMemory, moved
from pluto_motion.vector_follower import VectorFollower

__all__ = ['run_avoider']


def run_avoider(walls: Sequence[Segment], start: tuple[float, float, float], goal: tuple[float, float], *,
                noise: float = 0.0, seed: int = 0, dt: float = 0.05, limit_s: float = 90.0,
                settings: AvoidSettings = AvoidSettings(), memory: bool = True,
                scan_period: float | None = None, latency: float = 0.0, stamped: bool = True) -> Run:
    """Drive from ``start`` to the world point ``goal``; ``noise`` is the laser's range noise (m);
    ``memory`` False: the avoider looks at the last scan only (as before :mod:`pluto_motion.scan_memory`);
    ``scan_period``, ``latency``, ``stamped``: see the module docstring (a multiple of ``dt`` each).
    The result is 'reached' (the avoider's reach) or 'timeout'; nothing else ends a run."""
    rng = np.random.default_rng(seed)
    x, y, theta = start
    mover = VectorFollower()
    kept, view = ScanMemory(), LaserView(float(LASER.x[0]), 0.0, float(LASER.theta[0]), float(LASER.theta[-1]))
    side = 0
    path = [start]
    low = clearance(walls, x, y)
    t = 0.0
    period = dt if scan_period is None else scan_period
    centre = 0.0                # the next scan's centre time
    scan = None                 # the last scan that reached the avoider: points, where it was placed
    while t < limit_s:
        while centre + latency <= t + 1e-9:
            px, py, pt = path[round(centre / dt)]
            ranges = raycast(walls, px + 0.2 * math.cos(pt), py + 0.2 * math.sin(pt), pt + LASER.theta)
            if noise:
                ranges = ranges + rng.normal(0.0, noise, ranges.shape)
            placed = (px, py, pt) if stamped else (x, y, theta)
            scan = (LASER.points(ranges), placed)
            if memory:
                kept.add(placed, scan[0], view)
            centre += period
        if scan is None:                    # no scan yet: the avoider stops the robot
            mover.stop()
            t += dt
            path.append((x, y, theta))
            continue
        points, placed = scan
        if not stamped:
            placed = (x, y, theta)          # the scan taken for one from where the robot is now
        if memory:
            points = np.concatenate((points, kept.unseen(placed, view)))
        if placed != (x, y, theta):
            points = moved(points, placed, (x, y, theta))
        c, s = math.cos(theta), math.sin(theta)
        dx, dy = goal[0] - x, goal[1] - y
        choice = choose(points, (dx * c + dy * s, -dx * s + dy * c), settings, side, theta)
        side = choice.side
        if choice.reached:
            return Run('reached', path, low, t)
        move = None if choice.blocked else navigator_move(
            points, choice.length, choice.heading, settings.radius + settings.safety, NAV_TURN_STEP)
        if move is not None and move[0] > 0.0:
            length, heading = move
            mover.set_goal(x + length * math.cos(theta + heading), y + length * math.sin(theta + heading))
        else:
            mover.stop()
        out = mover.step((x, y, theta), DEFAULT_TV, DEFAULT_RV)
        x, y = x + out.tv * dt * math.cos(theta), y + out.tv * dt * math.sin(theta)
        theta = math.remainder(theta + out.rv * dt, math.tau)
        t += dt
        path.append((x, y, theta))
        low = min(low, clearance(walls, x, y))
    return Run('timeout', path, low, t)
