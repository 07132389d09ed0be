"""The simulated robot: a base moving in a world, with odometry, sonar, bumpers and battery.

Pluto's dummy base (5) moves as commanded, with odometry that has "no error" and a laser "based on
the odometer position and a map"; here the odometry error is configurable (zero by default, as in
the seed), and the truth is kept apart from the odometry so tests and plots can compare them.
Everything random comes from one seeded source, and time advances in the caller's fixed steps, so
a run with the same seed and commands repeats exactly.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .body import Battery, BumperRing, SonarRing
from .kinematics import BaseState, DriveLimits, arc, step_base
from .world import World

__all__ = ['OdometryNoise', 'RobotSpec', 'SimRobot']


@dataclasses.dataclass(frozen=True)
class OdometryNoise:
    """Odometry error: white noise proportional to motion, and a steady drift.

    ``trans`` is the standard deviation of the distance error per metre driven (fraction),
    ``rot`` that of the heading error per radian turned (fraction), ``drift`` a heading error in
    rad per metre driven (a wheel slightly smaller than the other). All 0 by default (Pluto 5).
    """

    trans: float = 0.0
    rot: float = 0.0
    drift: float = 0.0

    @property
    def is_zero(self) -> bool:
        return self.trans == 0.0 and self.rot == 0.0 and self.drift == 0.0


@dataclasses.dataclass(frozen=True)
class RobotSpec:
    """What the simulated base is: drive limits, body, sensors, odometry error."""

    limits: DriveLimits = DriveLimits()
    sonar: SonarRing = SonarRing()
    bumpers: BumperRing = BumperRing()
    odometry_noise: OdometryNoise = OdometryNoise()


class SimRobot:
    """A robot in a :class:`~.world.World`.

    Call :meth:`command` with velocities and :meth:`step` with the time step; read :attr:`truth`,
    :attr:`odometry`, :meth:`sonar`, :attr:`bumpers`, :attr:`battery`.
    """

    def __init__(self, world: World, spec: RobotSpec, rng: np.random.Generator, *,
                 start: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        self.world = world
        self.spec = spec
        self.rng = rng
        self.start = start
        self.truth = BaseState(*start)
        #: Odometry in its own frame, which starts at (0, 0, 0) where the robot started.
        self.odometry = BaseState()
        self.battery = Battery()
        self.tv_command = 0.0
        self.rv_command = 0.0
        self.bumpers = (False, False)
        #: Set when a bumper stopped the base; cleared by the next command.
        self.bumper_stop = False
        self.distance = 0.0
        if world.circle_collides(start[:2], spec.bumpers.radius):
            raise ValueError(f'start pose {start} is closer than the robot radius '
                             f'{spec.bumpers.radius} m to a wall')

    def command(self, tv: float, rv: float) -> None:
        """Set the commanded velocities (m/s, rad/s); held until the next command."""
        self.tv_command = tv
        self.rv_command = rv
        self.bumper_stop = False

    def stop(self) -> None:
        self.command(0.0, 0.0)

    def step(self, dt: float) -> None:
        """Advance ``dt`` seconds of simulated time."""
        before = self.truth
        after = step_base(before, self.tv_command, self.rv_command, self.spec.limits, dt)
        free = self.world.first_contact((before.x, before.y), (after.x, after.y), self.spec.bumpers.radius)
        if free < 1.0:
            # The footprint reaches a wall: it stops there, the bumper trips, the base stops.
            x = before.x + free * (after.x - before.x)
            y = before.y + free * (after.y - before.y)
            after = BaseState(x, y, after.theta, 0.0, 0.0, -before.tv / dt)
            self.tv_command = self.rv_command = 0.0
            self.bumper_stop = True
        self.truth = after
        self.bumpers = self.spec.bumpers.pressed(self.world, after.x, after.y, after.theta)
        self._odometry_step(before, after, dt)
        self.battery.drain(after.tv, dt)

    def _odometry_step(self, before: BaseState, after: BaseState, dt: float) -> None:
        ds = math.hypot(after.x - before.x, after.y - before.y)
        if after.tv < 0:
            ds = -ds
        dtheta = after.theta - before.theta
        noise = self.spec.odometry_noise
        if not noise.is_zero:
            ds += float(self.rng.normal(0.0, noise.trans * math.sqrt(abs(ds)))) if noise.trans else 0.0
            dtheta += (float(self.rng.normal(0.0, noise.rot * math.sqrt(abs(dtheta))))
                       if noise.rot else 0.0) + noise.drift * abs(ds)
        odo = self.odometry
        if noise.is_zero:
            # Exactly the truth, in the frame that starts at the start pose.
            x, y, theta = self._in_start_frame(after)
        else:
            rv = dtheta / dt if dt > 0 else 0.0
            tv = ds / dt if dt > 0 else 0.0
            x, y, theta = arc(odo.x, odo.y, odo.theta, tv, rv, dt)
        self.distance += abs(ds)
        self.odometry = BaseState(x, y, theta, after.tv, after.rv, after.acceleration)

    def _in_start_frame(self, state: BaseState) -> tuple[float, float, float]:
        sx, sy, st = self.start
        dx, dy = state.x - sx, state.y - sy
        c, s = math.cos(st), math.sin(st)
        return c * dx + s * dy, -s * dx + c * dy, state.theta - st

    def sonar(self) -> 'np.ndarray':
        t = self.truth
        return self.spec.sonar.ranges(self.world, t.x, t.y, t.theta)
