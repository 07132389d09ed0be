"""The driveModule's control (Pluto 6.1), free of any I/O: from the last accepted command, the
bumpers, the sonar and the heading, the velocities to write to the base and the status code.

Pluto 6.1: "The driveModule provides some collision protection, dynamic constraints and a
regulation loop to hold a heading.  It stops the robot if the bumpers are pressed and limits the
accelerations."  Per step, in this order:

1. Timeout: "The drive will also timeout after not getting any new command for about 4 seconds ...
   in case the user interface crashes" -> the command becomes a stop, element[0] = -1 until the next
   command.  The seed's exception ("If one is using the avoidModule goto this timeout will not
   occur") holds because the avoid goto rewrites its regulator command every cycle; nothing here
   exempts a sender, so a crashed avoidModule stops the robot too.
2. The wanted velocities: velocity mode as given; regulator mode turns smoothly to the heading
   (angular velocity proportional to the heading error, linear speed scaled by the cosine of the
   error and zero while the error exceeds 90 degrees), then holds it on a straight line.
3. Acceleration limits: the output moves toward the wanted velocities by at most ``accel * dt``.
4. Protection, applied after the ramp so that slowing is immediate and speeding up again is
   ramped: a pressed bumper forbids motion towards it (element[0] 1 front, 2 back, latched until
   the next command); sonar protection (cmdFlags + 10) slows and stops (3, 4, 5), and with no
   recent sonar reading it stops (fail closed, code of the direction of travel).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

from .drive_command import STOP, DriveCommand, Mode
from .scan_points import wrap
from .sonar_guard import BACK, FRONT, SonarGuard, SonarLimits

__all__ = ['BACK_BUMPER', 'FRONT_BUMPER', 'NORMAL', 'THREAD_STOPPED', 'TIMEOUT', 'DriveController',
           'DriveSettings']

#: element[0] codes of ``drive/status`` (Pluto 6.1); 3, 4, 5 are the sonar groups.
NORMAL, TIMEOUT, THREAD_STOPPED, FRONT_BUMPER, BACK_BUMPER = 0, -1, -10, 1, 2


@dataclasses.dataclass(frozen=True)
class DriveSettings:
    """Dynamic constraints and the regulator's gain."""

    max_tv: float = 1.0          # m/s
    max_rv: float = 1.5          # rad/s
    tv_accel: float = 0.5        # m/s^2
    rv_accel: float = 1.5        # rad/s^2
    timeout: float = 4.0         # s without a command (Pluto 6.1: "about 4 sec")
    heading_gain: float = 1.5    # rad/s per rad of heading error
    sonar: SonarLimits = SonarLimits()

    def __post_init__(self) -> None:
        for name in ('max_tv', 'max_rv', 'tv_accel', 'rv_accel', 'timeout', 'heading_gain'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f'{name} must be a positive number, not {value}')



def _clamp(value: float, bound: float) -> float:
    return max(-bound, min(bound, value))


def _toward(current: float, wanted: float, step: float) -> float:
    return current + _clamp(wanted - current, step)


class DriveController:
    """The drive's state; call :meth:`accept`, :meth:`set_bumpers` as inputs arrive and
    :meth:`step` once per loop."""

    def __init__(self, settings: DriveSettings = DriveSettings()) -> None:
        self.settings = settings
        self.guard = SonarGuard(settings.sonar)
        self.command: DriveCommand = STOP
        self.last_command: float | None = None
        self.running = True
        self.timed_out = False
        self.bumpers = (False, False)
        self.bumper_code = 0
        self.output = (0.0, 0.0)
        self.code = NORMAL

    # -- inputs ----------------------------------------------------------------------------------
    def accept(self, command: DriveCommand, now: float) -> None:
        """A new command: the timeout and a latched bumper stop are over (a bumper still pressed
        keeps forbidding motion towards it)."""
        self.command = command
        self.last_command = now
        self.timed_out = False
        self.bumper_code = 0

    def set_running(self, running: bool) -> None:
        """Start or stop the drive thread; stopping forgets the command."""
        if running == self.running:
            return
        self.running = running
        self.command, self.last_command, self.timed_out = STOP, None, False
        self.output = (0.0, 0.0)

    def set_bumpers(self, front: bool, back: bool) -> bool:
        """The bumpers' state; True when one was newly pressed (the stop then happens at once)."""
        newly = (front and not self.bumpers[0]) or (back and not self.bumpers[1])
        self.bumpers = (front, back)
        if newly:
            self.bumper_code = FRONT_BUMPER if front else BACK_BUMPER
            self.command = STOP
            self.output = (0.0, 0.0)
        return newly

    # -- one loop --------------------------------------------------------------------------------
    def step(self, now: float, dt: float, *, heading: float | None,
             sonar: Sequence[float] | None) -> tuple[float, float]:
        """The velocities (m/s, rad/s) to command now; :attr:`code` is the status element[0].

        :param heading: the robot's heading in the command's frame (None: unknown; a regulator
            command then stops).
        :param sonar: the latest sonar ranges, None when there is no recent reading.
        """
        s = self.settings
        if not self.running:
            self.output, self.code = (0.0, 0.0), THREAD_STOPPED
            return self.output
        if (self.last_command is not None and not self.timed_out
                and now - self.last_command > s.timeout):
            self.timed_out = True
            self.command = STOP
        wanted, rv = self._wanted(heading)
        wanted = _clamp(wanted, s.max_tv)
        tv = _toward(self.output[0], wanted, s.tv_accel * dt)
        rv = _toward(self.output[1], _clamp(rv, s.max_rv), s.rv_accel * dt)
        tv, safety = self._protect(tv, wanted, sonar)
        self.output = (tv, rv)
        if self.bumper_code:
            self.code = self.bumper_code
        elif self.timed_out:
            self.code = TIMEOUT
        else:
            self.code = safety
        return self.output

    def _wanted(self, heading: float | None) -> tuple[float, float]:
        c = self.command
        if c.mode is Mode.VELOCITY:
            return c.tv, c.rv
        if heading is None:
            return 0.0, 0.0
        error = wrap(c.heading - heading)
        return c.tv * max(0.0, math.cos(error)), self.settings.heading_gain * error

    def _protect(self, tv: float, wanted: float, sonar: Sequence[float] | None) -> tuple[float, int]:
        front, back = self.bumpers
        if front and tv > 0:
            tv = 0.0
        if back and tv < 0:
            tv = 0.0
        if not self.command.sonar or tv == 0.0:
            return tv, NORMAL
        if sonar is None or not self.guard.ready:
            return 0.0, FRONT if tv > 0 else BACK
        # The allowed speed is the drive's maximum times the free way's fraction: a function of the
        # distance alone.  From the speed asked for, a slow command (an avoid goto near its goal,
        # already slowed for the same wall) fell under the creep speed and stopped 0.5 m from the
        # wall, 0.3 m short of goals 0.6 m from it (a generated map in `make bench-motion`).
        return self.guard.limit(tv, sonar, max(abs(wanted), self.settings.max_tv))
