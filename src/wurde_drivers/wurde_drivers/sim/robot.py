"""The simulated robot: a base moving in a world, with odometry, sonar, bumpers and battery.

Pluto's dummy base (5) moves as commanded, with odometry that has "no error" and a laser "based on
the odometer position and a map"; here the odometry error is configurable (zero by default, as in
the seed), and the truth is kept apart from the odometry so tests and plots can compare them.
Everything random comes from one seeded source, and time advances in the caller's fixed steps, so
a run with the same seed and commands repeats exactly.

People (:mod:`.people`) are met at the stamp each step ends at: the robot cannot drive into one
(it stops there, as at a wall), and a person whose body comes to touch the robot — walking into
it, or driven into — presses a bumper and stops the base.  Each such contact counts once, from
the step it begins until the person has let go (:attr:`SimRobot.person_contacts`); the person
walks on through the robot, which it does not push.
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
    ``scale`` and ``turn_scale`` are a calibration error (Pluto 7.1: the calibration "needs to be
    set after changes to tire pressure"): the odometry counts ``scale`` times the distance driven
    and ``turn_scale`` times the angle turned (1: none).
    """

    trans: float = 0.0
    rot: float = 0.0
    drift: float = 0.0
    scale: float = 1.0
    turn_scale: float = 1.0

    @property
    def is_zero(self) -> bool:
        return (self.trans == 0.0 and self.rot == 0.0 and self.drift == 0.0 and self.scale == 1.0
                and self.turn_scale == 1.0)


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
                 start: tuple[float, float, float] = (0.0, 0.0, 0.0), now: float = 0.0) -> None:
        """``now``: the stamp of the start (the people's clock, :mod:`.walk`)."""
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
        #: The stamp of :attr:`truth`.
        self.now = now
        #: Contacts with people so far, each counted once; those that began in the last step.
        self.person_contacts = 0
        self.new_person_contacts: list[int] = []
        self._touching: set[int] = set()
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

    def step(self, dt: float, *, now: float | None = None) -> None:
        """Advance ``dt`` seconds of simulated time, to the stamp ``now`` (default: the last
        stamp plus ``dt``), where the people are met."""
        now = self.now + dt if now is None else now
        before = self.truth
        after = step_base(before, self.tv_command, self.rv_command, self.spec.limits, dt)
        bumpers = self.spec.bumpers
        free = self.world.first_contact((before.x, before.y), (after.x, after.y), bumpers.radius, at=now)
        stop = free < 1.0
        if stop:
            # The footprint reaches a wall or a person: it stops there, the bumper trips.
            after = dataclasses.replace(after, x=before.x + free * (after.x - before.x),
                                        y=before.y + free * (after.y - before.y))
        touching = {index for index, _ in self.world.people_within((after.x, after.y), bumpers.reach, now)}
        self.new_person_contacts = sorted(touching - self._touching)
        self.person_contacts += len(self.new_person_contacts)
        self._touching = touching
        if stop or self.new_person_contacts:
            # A bumper tripped (a person walking into the robot too): the base stops.
            after = BaseState(after.x, after.y, after.theta, 0.0, 0.0, -before.tv / dt)
            self.tv_command = self.rv_command = 0.0
            self.bumper_stop = True
        self.truth = after
        self.now = now
        self.bumpers = bumpers.pressed(self.world, after.x, after.y, after.theta, at=now)
        self._odometry_step(before, after, dt)
        self.battery.drain(after.tv, dt)

    def _odometry_step(self, before: BaseState, after: BaseState, dt: float) -> None:
        ds = math.hypot(after.x - before.x, after.y - before.y)
        if after.tv < 0:
            ds = -ds
        dtheta = after.theta - before.theta
        noise = self.spec.odometry_noise
        if not noise.is_zero:
            ds, dtheta = ds * noise.scale, dtheta * noise.turn_scale
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
        return self.spec.sonar.ranges(self.world, t.x, t.y, t.theta, at=self.now)
