"""One actuated joint moving toward a target under velocity and acceleration limits.

Used by the dummy wrist (Pluto 8.3: pan and tilt in rad, rad/s, rad/s²; "one must set both the
velocity and acceleration > 0 if you want the position to change"). The profile is the one the
wrist and PTU emulators use (:mod:`wurde_drivers.motion`), within the joint's limits.
"""

from __future__ import annotations

import dataclasses

from ..motion import ramp_step, stopping_distance

__all__ = ['Axis']


@dataclasses.dataclass
class Axis:
    """State and command of one joint; :meth:`step` advances it ``dt`` seconds."""

    minimum: float
    maximum: float
    max_velocity: float
    max_acceleration: float
    position: float = 0.0
    velocity: float = 0.0
    acceleration: float = 0.0
    target: float = 0.0
    speed: float = 0.0      # commanded velocity bound (rad/s)
    accel: float = 0.0      # commanded acceleration (rad/s²)

    def command(self, target: float, speed: float, accel: float) -> bool:
        """Aim at ``target`` (clamped to the limits); False when speed or accel is not > 0."""
        if speed <= 0.0 or accel <= 0.0:
            return False
        self.target = min(self.maximum, max(self.minimum, target))
        self.speed = min(speed, self.max_velocity)
        self.accel = min(accel, self.max_acceleration)
        return True

    def halt(self) -> None:
        """Stop as fast as the acceleration allows: the target becomes the stopping point."""
        stop = stopping_distance(self.velocity, self.accel or self.max_acceleration)
        self.target = min(self.maximum, max(self.minimum, self.position + stop))

    @property
    def moving(self) -> bool:
        return self.velocity != 0.0 or abs(self.target - self.position) > 1e-9

    def step(self, dt: float) -> None:
        """Advance ``dt`` seconds along the shared profile; ``acceleration`` is the step's."""
        previous = self.velocity
        self.position, self.velocity = ramp_step(self.position, self.velocity, self.target,
                                                 self.speed, self.accel, dt)
        self.acceleration = (self.velocity - previous) / dt if dt > 0.0 else 0.0
