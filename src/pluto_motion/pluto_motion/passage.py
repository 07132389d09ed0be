"""Timing the robot's passage past people who walk: go on, wait or back off, whichever keeps clear.

Slowing for what is ahead (:class:`~pluto_motion.laser_guard.LaserGuard`) is the wrong answer to a
person walking at the robot's side: braking leaves the robot standing on the person's line, and a
walker who does not yield walks into it.  :func:`passage_speed` plans the robot's speed along its
heading over the next :attr:`PassageSettings.horizon` seconds in the space of time and travel:
each candidate is a speed the robot turns to at its acceleration limit (from backing off through
stopping to the speed wanted, or a step forward when it wants less); each walker
(:class:`~pluto_motion.moving_obstacles.MovingObstacles`' moving tracks, a disc each) goes on at its
velocity.  The candidate nearest the speed wanted that keeps every walker's body
:attr:`PassageSettings.margin` from the robot's footprint wins; when none does, the one that keeps
furthest from them.  Going on when the walker's line is behind the robot, waiting short of a line
the walker is about to cross, backing off from one who comes at the robot and stepping out of the
way of one who comes at a robot standing or turning on the spot are the same rule.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

__all__ = ['PassageSettings', 'Walker', 'passage_speed']


@dataclasses.dataclass(frozen=True)
class PassageSettings:
    """The robot and the plan (metres, seconds)."""

    radius: float = 0.35        #: the robot's footprint
    margin: float = 0.15        #: the least gap wanted between the footprint and a walker's body
    horizon: float = 3.0        #: s planned ahead
    dt: float = 0.1             #: s between the planned places
    accel: float = 0.5          #: m/s^2 the robot's speed changes by at most (the drive's tv_accel)
    latency: float = 0.1        #: s before a speed commanded now starts to change the robot's
    back: float = 0.3           #: m/s the robot may back off at (0: never)
    choices: int = 10           #: candidate speeds between backing off and the speed wanted


@dataclasses.dataclass(frozen=True)
class Walker:
    """A walking thing in the robot frame: its body (a disc: centre (2,), radius) and velocity (2,)."""

    centre: NDArray
    radius: float
    velocity: NDArray


def _travel(v0: float, target: float, settings: PassageSettings, times: NDArray) -> NDArray:
    """How far along its heading the robot is at ``times`` when, after the latency, it turns its
    speed from ``v0`` to ``target`` at the acceleration limit and holds it."""
    ramp = abs(target - v0) / settings.accel
    sign = 1.0 if target >= v0 else -1.0
    late = np.minimum(times, settings.latency)
    t = times - late
    during = v0 * t + 0.5 * sign * settings.accel * t ** 2
    at_end = v0 * ramp + 0.5 * sign * settings.accel * ramp ** 2
    return v0 * late + np.where(t <= ramp, during, at_end + target * (t - ramp))


def _least_gap(travel: NDArray, walkers: list[Walker], times: NDArray, radius: float) -> float:
    """The least gap between the footprint, at ``travel`` along x at ``times``, and the walkers."""
    least = math.inf
    for w in walkers:
        dx = w.centre[0] + w.velocity[0] * times - travel
        dy = w.centre[1] + w.velocity[1] * times
        least = min(least, float(np.sqrt(np.min(dx * dx + dy * dy))) - radius - w.radius)
    return least


def passage_speed(walkers: list[Walker], speed: float, wanted: float, settings: PassageSettings = PassageSettings(),
                  ahead: float = 0.0) -> tuple[float, float] | None:
    """The speed (m/s along the robot's heading) to command now against ``walkers``, and the least
    gap it keeps; None when the speed ``wanted`` keeps the margin (nothing to do).  ``speed`` is the
    robot's speed now; ``ahead`` the fastest it may step forward out of a walker's way when it wants
    to go slower (standing, or turning on the spot: what is ahead allows it).

    Of the candidates that keep the margin the one nearest the speed wanted wins (the fastest when
    the robot wants to drive on); when none does, the one that keeps furthest from the walkers."""
    if not walkers:
        return None
    s = settings
    times = np.arange(s.dt, s.horizon + 0.5 * s.dt, s.dt)
    wanted = max(wanted, 0.0)
    top = max(wanted, ahead)
    candidates = sorted({wanted, *np.linspace(top, -s.back, s.choices + 1).tolist()}, key=lambda v: abs(v - wanted))
    best: tuple[float, float] | None = None
    for target in candidates:
        gap = _least_gap(_travel(speed, float(target), s, times), walkers, times, s.radius)
        if gap >= s.margin:
            return None if target == wanted else (float(target), gap)
        if best is None or gap > best[1] + 1e-3:
            best = (float(target), gap)
    return best
