"""One actuated joint moving toward a target under velocity and acceleration limits.

Used by the dummy wrist (Pluto 8.3: pan and tilt in rad, rad/s, rad/s²; "one must set both the
velocity and acceleration > 0 if you want the position to change"). The profile is trapezoidal:
accelerate at ``acceleration`` up to ``velocity``, and brake in time to stop on the target
(``v² = 2 a d``), within the joint's limits.
"""

from __future__ import annotations

import dataclasses
import math

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
        a = self.accel or self.max_acceleration
        stop = self.velocity * abs(self.velocity) / (2 * a) if a > 0 else 0.0
        self.target = min(self.maximum, max(self.minimum, self.position + stop))

    @property
    def moving(self) -> bool:
        return self.velocity != 0.0 or abs(self.target - self.position) > 1e-9

    def step(self, dt: float) -> None:
        remaining = self.target - self.position
        if self.accel <= 0.0 or self.speed <= 0.0 or dt <= 0.0 or (remaining == 0.0 and self.velocity == 0.0):
            self.velocity = self.acceleration = 0.0
            return
        direction = math.copysign(1.0, remaining) if remaining else 0.0
        a_dt = self.accel * dt
        if abs(self.velocity) <= a_dt + 1e-12 and abs(remaining) <= max(abs(self.velocity) * dt, 1e-9):
            # Close enough to stop on the target within one step of braking.
            self.acceleration = -self.velocity / dt
            self.position, self.velocity = self.target, 0.0
            return
        # The fastest speed from which whole steps of braking still stop on the target:
        # the distance of braking from v in steps of a·dt is dt·v·(v/(a·dt) + 1)/2.
        brake_speed = (-a_dt + math.sqrt(a_dt * a_dt + 8 * self.accel * abs(remaining))) / 2
        wanted = direction * min(self.speed, brake_speed)
        change = max(-a_dt, min(a_dt, wanted - self.velocity))
        self.velocity += change
        self.acceleration = change / dt
        self.position += self.velocity * dt
