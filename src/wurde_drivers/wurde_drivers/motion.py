"""The one trapezoidal motion profile of a pan/tilt axis, shared by the PTU-46 emulator, the CAN
wrist emulator and the dummy wrist (Pluto 8.3; PTU-D46 manual 4.4.4: symmetric acceleration).

An axis accelerates at ``accel`` up to ``speed`` and brakes in time to stop on its target.  The
braking maths is that of the simulation's own steps: the velocity changes by at most ``a·dt`` per
step and then the position moves by ``v·dt``, so braking from ``v`` in whole steps covers
``dt·v·(v/(a·dt) + 1)/2``; the fastest speed that still stops on the target from distance ``d`` is
therefore ``(−a·dt + sqrt((a·dt)² + 8·a·d)) / 2`` — the continuous ``v² = 2·a·d`` as ``dt → 0``,
but exact for the steps taken, so an axis lands on its target instead of overshooting it.  An
emulator steps in wall-clock time, so a step can be longer than the one braking planned for; a
step that would pass the target stops on it.

Pure Python, any units (rad or PTU positions) as long as they agree.
"""

from __future__ import annotations

import math

__all__ = ['braking_speed', 'ramp_step', 'stopping_distance']


def braking_speed(distance: float, accel: float, dt: float) -> float:
    """The fastest speed from which steps of ``dt`` at deceleration ``accel`` stop within ``distance``.

    :param distance: the distance left, ≥ 0.
    :param accel: the deceleration, ≥ 0.
    :param dt: the step, s, ≥ 0.
    """
    a_dt = accel * dt
    return (-a_dt + math.sqrt(a_dt * a_dt + 8.0 * accel * distance)) / 2.0


def stopping_distance(velocity: float, accel: float) -> float:
    """Signed distance an axis moving at ``velocity`` covers while braking at ``accel``.

    :param velocity: signed, units per second.
    :param accel: the deceleration (> 0; otherwise the distance is 0).
    """
    return velocity * abs(velocity) / (2.0 * accel) if accel > 0.0 else 0.0


def ramp_step(position: float, velocity: float, target: float, speed: float, accel: float,
              dt: float) -> tuple[float, float]:
    """One step of ``dt`` toward ``target``: the new ``(position, velocity)``.

    With ``speed``, ``accel`` or ``dt`` not positive the axis stops where it is.

    :param position: where the axis is.
    :param velocity: its signed velocity now.
    :param target: where it is to stop.
    :param speed: bound of the velocity's magnitude.
    :param accel: bound of the velocity's change per second.
    :param dt: the step, s.
    """
    remaining = target - position
    if accel <= 0.0 or speed <= 0.0 or dt <= 0.0 or (remaining == 0.0 and velocity == 0.0):
        return position, 0.0
    a_dt = accel * dt
    if abs(velocity) <= a_dt + 1e-12 and abs(remaining) <= max(abs(velocity) * dt, 1e-9):
        return target, 0.0            # close enough to stop on the target within one step
    direction = math.copysign(1.0, remaining) if remaining else 0.0
    wanted = direction * min(speed, braking_speed(abs(remaining), accel, dt))
    velocity += max(-a_dt, min(a_dt, wanted - velocity))
    position += velocity * dt
    if (target - position) * remaining < 0.0 and abs(target - position) > 1e-9:
        # Passed: only a step longer than the one braking planned for (an emulator stepping in
        # wall-clock time) gets here; the axis stops on its target.
        return target, 0.0
    return position, velocity
