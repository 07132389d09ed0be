"""drive_module: Pluto's driveModule (Pluto 6.1), the first link of the movement chain (Pluto 4).

It reads its command interface ``drive/command`` (ActuatorState requests: 0 velocity, 1 the
heading regulator, 10 and 11 the same with sonar protection, -1 release) and writes the base's
command ``<base>Command`` (ActuatorState, cmdFlags 0 only: velocity[0..1] = linear, angular),
"after possibly modifying the command" (Pluto 4): collision protection, acceleration limits and a
regulator that holds a heading (:mod:`pluto_motion.drive_control`; the heading's fall-backs:
:mod:`pluto_motion.heading_source`).  ``drive/status`` (FVectorState) tells what it commanded and
why.  At start it sets the odometry calibration file (``-k``) in the base (Pluto 6.1;
:mod:`pluto_motion.base_calibration`).

docs/movement.md ("Movement", driveModule) has the tables of ``drive/command`` and ``drive/status``,
the options and the calibration file; docs/pluto-motion.md ("driveModule") adds what that page
leaves out.  The five limits (``max_tv``, ``max_rv``, ``tv_accel``, ``rv_accel``, ``timeout``)
are tunables starting from the options.

Before changing it: a command that is not valid is refused whole and the last good one goes on;
without a command for the timeout (Pluto 6.1's "about 4 sec") the base is stopped, so a crashed
module above never leaves the robot driving.  A released drive (-1) writes nothing more to the
base, so that another program may drive it.
"""

from __future__ import annotations

import math
import os
import sys
import time
from typing import Any

from wurde_core import CommsManager, Logger
from wurde_core.interfaces import ActuatorState, Bumper, RangeFinder
from wurde_core.module_loop import config_file, run_loop, set_loop
from wurde_idl.errors import ConfigError

from pluto_nav.odometry_calibration import DEFAULT_FILE, Calibration, read_calibration
from wurde_core.parameters import TunedSettings

from .base_calibration import BaseCalibration
from .chain_link import ChainLink
from .drive_command import COMMAND, STATUS, DriveCommand, Mode, parse_command
from .drive_control import DriveController, DriveSettings
from .heading_source import HeadingSource
from .sonar_guard import ring_layout

__all__ = ['COMMAND', 'STATUS', 'DriveModule', 'main']

LOOP_S = 0.05
#: A sonar reading older than this (s) is no reading: sonar protection then stops the robot.
SONAR_FRESH_S = 1.0
#: Longest time step the ramps use (a stalled loop must not allow a jump).
MAX_DT = 0.2
OPTIONS = {'v': 'max_tv', 'w': 'max_rv', 'a': 'tv_accel', 'A': 'rv_accel', 't': 'timeout'}
#: The limits as tunables (ROS 2 parameters ``ros2 param set /driveModule max_tv 0.5``): what
#: each means, its unit, and its range.
TUNABLES: dict[str, tuple[str, float | None, float | None]] = {
    'max_tv': ('linear velocity limit, m/s', 0.01, 5.0),
    'max_rv': ('angular velocity limit, rad/s', 0.01, 6.0),
    'tv_accel': ('linear acceleration limit, m/s^2', 0.01, 5.0),
    'rv_accel': ('angular acceleration limit, rad/s^2', 0.01, 10.0),
    'timeout': ('seconds without a command before the drive stops', 0.01, 60.0)}
HELP = ('  -b BASE      the base module (default PlutoBase): writes <BASE>Command, reads <BASE>Bumpers,\n'
        '               <BASE>Sonar, <BASE>Motion\n'
        '  -v MAX_TV    linear velocity limit, m/s (1.0)\n'
        '  -w MAX_RV    angular velocity limit, rad/s (1.5)\n'
        '  -a TV_ACCEL  linear acceleration limit, m/s^2 (0.5)\n'
        '  -A RV_ACCEL  angular acceleration limit, rad/s^2 (1.5)\n'
        '  -t TIMEOUT   seconds without a command before the drive stops (4)\n'
        '  -k FILE      the odometry calibration set in the base at start (default\n'
        '               odometry-calibration.yaml in the config directory, if there is one)')


class DriveModule:
    """The driveModule's streams around a :class:`DriveController`."""

    def __init__(self, manager: CommsManager, logger: Logger, settings: DriveSettings, *, base: str,
                 calibration: Calibration | None = None) -> None:
        self.manager, self.logger = manager, logger
        self.control = DriveController(settings)
        self.link = ChainLink(manager, logger, COMMAND, STATUS,
                              parse=lambda flags, velocity, position, _force: parse_command(flags, velocity, position),
                              accept=self._accept, set_running=self._set_running,
                              running=lambda: self.control.running)
        self.base = ActuatorState(f'{base}Command')
        self.bumpers = Bumper(f'{base}Bumpers')
        self.bumpers.set_queue_mode(True)           # a short press is not missed
        self.sonar = RangeFinder(f'{base}Sonar')
        for obj in (self.base, self.bumpers, self.sonar):
            manager.register_consumer(obj)
        self.heading = HeadingSource(manager, base, lambda text: logger.warn(f'{manager.name}: {text}'))
        self.ranges: list[float] | None = None
        #: The sonar ring's uniform layout (first bearing, step, first x, y, half angle), when its
        #: info gives no sensor positions.
        self.uniform: tuple[float, float, float, float, float] | None = None
        self.ranges_at = -math.inf
        self.last_step = time.monotonic()
        self.loop_stamp = manager.now()    # the instant the current loop began (ROS clock)
        self.link.commands.set_auto_timestamp(False)
        self.base_stopped = False
        self.tuned = TunedSettings(manager, settings, TUNABLES)
        self.calibration = (BaseCalibration(self.base, calibration,
                                            lambda text: logger.notice(f'{manager.name}: {text}'))
                            if calibration is not None else None)

    # -- inputs ----------------------------------------------------------------------------------
    def _accept(self, command: DriveCommand, now: float) -> None:
        self.control.accept(command, now)
        self._publish_command(command)

    def _set_running(self, running: bool) -> None:
        self.control.set_running(running)
        self.base_stopped = False

    def _take_sensors(self, now: float) -> None:
        while self.bumpers.get_next_data():
            pressed = list(self.bumpers.data.bumpers) + [False, False]
            if self.control.set_bumpers(bool(pressed[0]), bool(pressed[1])) and self.control.running:
                self._write_base(0.0, 0.0)          # at once, not at the end of the loop
                self.logger.warn(f'{self.manager.name}: {"front" if pressed[0] else "back"} bumper: stopped')
        while self.sonar.get_next_info():
            info = self.sonar.info
            positions = list(info.sensor_positions.get_value())
            half_angle = float(info.half_angle.get_value())
            if positions:
                self.control.guard.set_layout([(float(p.x()), float(p.y()), float(p.theta())) for p in positions],
                                              half_angle)
                self.uniform = None
            else:       # a uniform ring: laid out when a reading tells how many sensors there are
                self.uniform = (float(info.theta_offset.get_value()), float(info.theta_separation.get_value()),
                                float(info.x_offset.get_value()), float(info.y_offset.get_value()), half_angle)
        if self.sonar.get_next_data():
            self.ranges, self.ranges_at = [float(r) for r in self.sonar.data.ranges], now
            if self.uniform is not None and len(self.control.guard.sensors) != len(self.ranges):
                first, step, x0, y0, half_angle = self.uniform
                self.control.guard.set_layout(ring_layout(len(self.ranges), first, step, x0, y0), half_angle)

    # -- outputs ---------------------------------------------------------------------------------
    def _write_base(self, tv: float, rv: float) -> None:
        req = self.base.requests
        req.cmd_flags.set_value(0)
        req.velocity.set_value([tv, rv])
        self.base.publish_request()

    def _publish_command(self, command: DriveCommand) -> None:
        data = self.link.commands.data
        data.cmd_flags = command.cmd_flags
        data.velocity = [command.tv, command.rv] if command.mode is Mode.VELOCITY else [command.tv]
        data.position = [] if command.mode is Mode.VELOCITY else [0.0, command.heading]
        data.timestamp = self.loop_stamp   # accepted at the loop's instant, as the watchdog counts
        self.link.commands.publish_data()

    # -- one loop --------------------------------------------------------------------------------
    def step(self) -> None:
        self.control.settings = self.tuned.current()    # limits a user set as parameters
        now, self.loop_stamp = time.monotonic(), self.manager.now()   # one instant: rates, stamps
        dt, self.last_step = min(now - self.last_step, MAX_DT), now
        self.link.take_commands(now)
        if self.calibration is not None:
            self.calibration.step()
        self._take_sensors(now)
        self.heading.update()
        regulating = self.control.command.mode is Mode.REGULATOR and self.control.running
        heading = self.heading.heading() if regulating else None
        sonar = self.ranges if now - self.ranges_at <= SONAR_FRESH_S else None
        tv, rv = self.control.step(now, dt, heading=heading, sonar=sonar)
        if self.control.running:
            self._write_base(tv, rv)
        elif not self.base_stopped:
            self._write_base(0.0, 0.0)              # the thread stops: one stop, then hands off
            self.base_stopped = True
        self.link.publish_status(self.control.output, [self.control.code, self.link.refused,
                                                       int(self._ready(sonar))], now, self.loop_stamp)

    def _ready(self, sonar: list[float] | None) -> bool:
        """element[2] (ours): the base reads this drive's commands and the sonar protection has a
        fresh reading and the ring's layout, so a command, sonar-protected or not, can move the
        robot.  A program's first command waits for it (CARMEN's velocity command): modules
        started together find each other in any order, and a drive heard before it hears the base
        turns a short drive into none (CI: a 2 s drive of the manual's CARMEN program moved 0.00 m)."""
        return self.base.peers('request') > 0 and sonar is not None and self.control.guard.ready

    def close(self) -> None:
        """Leave the base stopped (idempotent)."""
        if self.control.running:
            self._write_base(0.0, 0.0)


def _settings(manager: CommsManager, user: dict[str, str]) -> DriveSettings:
    values: dict[str, Any] = {}                 # DriveSettings' keyword arguments
    for letter, field in OPTIONS.items():
        if letter in user:
            try:
                values[field] = float(user[letter])
            except ValueError:
                raise ValueError(f'-{letter} {user[letter]!r}: not a number') from None
    return DriveSettings(**values)


def _calibration(manager: CommsManager, given: str | None) -> Calibration | None:
    """The calibration file's values: ``-k``'s file (must exist), else the default one if any."""
    path = config_file(manager, given, DEFAULT_FILE)
    if not given and not os.path.exists(path):
        return None
    return read_calibration(path)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('driveModule')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'b:v:w:a:A:t:k:').user
    try:
        settings = _settings(manager, user)
        calibration = _calibration(manager, user.get('k'))
    except (ValueError, ConfigError) as error:
        print(f'drive_module: {error}', file=sys.stderr, flush=True)
        return 2
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    module = DriveModule(manager, logger, settings, base=user.get('b', 'PlutoBase'), calibration=calibration)
    set_loop(manager, LOOP_S)
    logger.notice(f'{manager.name}: driving {user.get("b", "PlutoBase")}Command; {settings}')
    return run_loop(manager, module.step, module.close)


if __name__ == '__main__':
    sys.exit(main())
