"""Base kinematics of the simulated robot: velocity commands, limits, and exact arc integration.

A synchro-drive (B21r) and a differential/skid drive (ATRV) both move as a unicycle: a translational
velocity ``tv`` along the heading and a rotational velocity ``rv`` about the vertical. Commands are
clamped to the velocity limits and reached through the acceleration limits (the seed's SynchroDrive
limits, WURDE 3.4.19); within one step the velocities are constant, so the pose follows the closed
form arc of a constant-curvature motion exactly (no Euler drift):

    x' = x + tv/rv (sin(θ + rv dt) − sin θ),  y' = y − tv/rv (cos(θ + rv dt) − cos θ),  θ' = θ + rv dt

and the straight line ``x' = x + tv dt cos θ`` when ``rv`` is 0.
"""

from __future__ import annotations

import dataclasses
import math

__all__ = ['BaseState', 'DriveLimits', 'arc', 'ramp', 'step_base']

#: |rv| below which the straight-line form is used (the arc form divides by rv).
_STRAIGHT = 1e-9


@dataclasses.dataclass(frozen=True)
class DriveLimits:
    """Velocity (m/s, rad/s) and acceleration (m/s², rad/s²) limits of a base."""

    max_tv: float = 1.0
    max_rv: float = 1.5
    tv_accel: float = 1.0
    rv_accel: float = 2.0


@dataclasses.dataclass(frozen=True)
class BaseState:
    """Pose (m, rad; θ unwrapped, so full turns are counted) and velocities of the base."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    tv: float = 0.0
    rv: float = 0.0
    acceleration: float = 0.0


def ramp(current: float, target: float, accel: float, dt: float) -> float:
    """Move ``current`` toward ``target`` by at most ``accel * dt`` (no limit if accel <= 0)."""
    if accel <= 0.0:
        return target
    step = accel * dt
    if target > current:
        return min(target, current + step)
    return max(target, current - step)


def arc(x: float, y: float, theta: float, tv: float, rv: float,
        dt: float) -> tuple[float, float, float]:
    """The pose after moving ``dt`` seconds at constant ``tv`` and ``rv`` (closed form)."""
    if abs(rv) < _STRAIGHT:
        return x + tv * dt * math.cos(theta), y + tv * dt * math.sin(theta), theta
    new_theta = theta + rv * dt
    radius = tv / rv
    return (x + radius * (math.sin(new_theta) - math.sin(theta)),
            y - radius * (math.cos(new_theta) - math.cos(theta)),
            new_theta)


def step_base(state: BaseState, tv_command: float, rv_command: float, limits: DriveLimits,
              dt: float) -> BaseState:
    """Advance the base by ``dt``: clamp the command, ramp the velocities, then move on the arc.

    The velocities reached at the start of the step are held for the whole step, so for a
    command already reached the pose is exactly the closed-form arc.
    """
    tv_target = max(-limits.max_tv, min(limits.max_tv, tv_command))
    rv_target = max(-limits.max_rv, min(limits.max_rv, rv_command))
    tv = ramp(state.tv, tv_target, limits.tv_accel, dt)
    rv = ramp(state.rv, rv_target, limits.rv_accel, dt)
    x, y, theta = arc(state.x, state.y, state.theta, tv, rv, dt)
    acceleration = (tv - state.tv) / dt if dt > 0 else 0.0
    return BaseState(x, y, theta, tv, rv, acceleration)
