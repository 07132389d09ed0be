"""avoid_module: Pluto's avoidModule (Pluto 6.2), the second link of the movement chain (Pluto 4).

It reads its command interface ``avoidance/command`` (ActuatorState requests) and writes the
driveModule's, ``drive/command``, "after possibly modifying the command" (Pluto 4); the drive's
``drive/status`` comes back up as ``avoidance/status``.  It reads the laser (``-l``, default
PlutoLaser: the RangeFinder of config/pluto's dummy SICK), the base's sonar ``<base>Sonar`` and the
pose (:class:`pluto_motion.pose_source.PoseSource`: Localization/Pose, else Dead-Reckoning, else the
base odometry, each fall-back warned once).

``avoidance/command`` (requests): cmdFlags = 10*A + T (:mod:`pluto_motion.avoid_command`):

====== ========================================================================================
 A      0 no avoidance, 1 sonar (the drive's +10), 2 laser (below), 3 both
 T      0 velocity, 1 regulator (heading in the Localization/Pose frame), 2 goto (position x, y;
        velocity = maximum linear, angular; force[0] goal strength), 3 wall follow (velocity[0]
        speed, position[0] camera-to-wall distance)
 -1     release the robot: the avoid thread stops, writes one stop to the drive, then nothing
====== ========================================================================================

Anything else, a missing field or a value that is not finite is refused whole, logged and counted.

``avoidance/status`` (FVectorState, on every change and once a second):

=================== ===============================================================================
data[0..1]          the velocities commanded: the drive's, or the avoidModule's slowed ones (6, 7)
element[0]          the drive's element[0] (0, -1, -10, 1..5), or 6 laser slow/stop, 7 laser fatal
                    error or no scan for longer than the laser's period allows (stop; fail closed)
element[1]          1 goto point reached (within 0.15 m), 2 goto stuck (no 0.2 m of progress in 10 s,
                    or an obstacle 3 cm from the footprint), -1 goto normal, -10 avoid thread
                    stopped, 0 otherwise
element[2] (ours)   the number of refused commands
=================== ===============================================================================

A request on ``avoidance/status`` writing element[0] = 0 starts the avoid thread and sends the drive
its start_activity (Pluto 6.2: "All threads can be started by sending a start_activity command ...
Threads will not care if you try to start them twice"); -10 stops it.

The loop runs on every laser scan (a trigger), every command and at least every
:data:`LOOP_S` seconds, so a scan's drive command goes out as soon as it is computed.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from wurde_core import CommsManager, Logger, Trigger
from wurde_core.interfaces import ActuatorState, FVectorState, RangeFinder
from wurde_core.module_loop import run_loop, set_loop

from . import drive_command
from .avoid_command import COMMAND, STATUS, AvoidCommand, CommandRefused, parse_command
from .avoid_control import THREAD_STOPPED, AvoidController, DriveOrder
from .goto_field import FieldSettings
from .laser_guard import GuardLimits
from .pose_source import PoseSource
from .scan_points import Beams

__all__ = ['COMMAND', 'STATUS', 'AvoidModule', 'Every', 'main']

#: Longest time between two loops (s) when no scan or command wakes the module.
LOOP_S = 0.05
#: Seconds between two publications of an unchanged status.
STATUS_PERIOD_S = 1.0
#: A sonar reading older than this (s) is left out of the goto's field.
SONAR_FRESH_S = 1.0
HELP = ('  -b BASE      the base module (default PlutoBase): reads <BASE>Sonar, <BASE>Motion\n'
        '  -l LASER     the laser (default PlutoLaser): RangeFinder stream LASER\n'
        '  -r RADIUS    the robot\'s radius, m (0.35)\n'
        '  -S STALE     seconds without a scan after which the laser is dead (default: from its period)')


class Every(Trigger):
    """A trigger that fires when ``period`` seconds have passed since it last fired: the loop's
    floor rate between the event triggers."""

    def __init__(self, period: float) -> None:
        super().__init__()
        self.period = period
        self.last = -math.inf

    def ready(self) -> bool:
        return time.monotonic() - self.last >= self.period

    def fire(self) -> bool:
        if not self.ready():
            return False
        self.last = time.monotonic()
        return True


def _beams(info: object) -> Beams:
    positions = list(info.sensor_positions.get_value())  # type: ignore[attr-defined]
    half = float(info.half_angle.get_value())  # type: ignore[attr-defined]
    if positions:
        return Beams.ring([(p.x(), p.y(), p.theta()) for p in positions], half)
    return Beams.fan(int(info.range_count.get_value()),  # type: ignore[attr-defined]
                     first=float(info.theta_offset.get_value()),  # type: ignore[attr-defined]
                     step=float(info.theta_separation.get_value()),  # type: ignore[attr-defined]
                     x=float(info.x_offset.get_value()), y=float(info.y_offset.get_value()),  # type: ignore[attr-defined]
                     half_angle=half)


class AvoidModule:
    """The avoidModule's streams around an :class:`AvoidController`."""

    def __init__(self, manager: CommsManager, logger: Logger, control: AvoidController, *,
                 base: str, laser: str) -> None:
        self.manager, self.logger, self.control = manager, logger, control
        self.commands = ActuatorState(COMMAND)
        self.commands.set_queue_mode(True)              # every request is judged (and counted)
        self.status = FVectorState(STATUS)
        self.drive = ActuatorState(drive_command.COMMAND)
        self.drive_status = FVectorState(drive_command.STATUS)
        self.laser = RangeFinder(laser)
        self.sonar = RangeFinder(f'{base}Sonar')
        for obj in (self.commands, self.status):
            manager.register_supplier(obj)
        for obj in (self.drive, self.drive_status, self.laser, self.sonar):
            manager.register_consumer(obj)
        for trigger in (Trigger(self.laser), Trigger(self.commands), Trigger(self.status), Every(LOOP_S)):
            manager.register_trigger(trigger)
        self.pose = PoseSource(manager, base, lambda text: logger.warn(f'{manager.name}: {text}'),
                               user='the goto and the regulator steer')
        self.laser_beams: Beams | None = None
        self.sonar_beams: Beams | None = None
        self.sonar_at = -math.inf
        self.refused = 0
        self.drive_data: list[float] = []
        self.drive_element: list[int] = []
        self.sent_status: tuple[list[float], list[int]] | None = None
        self.status_at = -math.inf
        self.failure: str | None = None

    # -- inputs ----------------------------------------------------------------------------------
    def _take_commands(self, now: float) -> None:
        while self.commands.get_next_request():
            r = self.commands.requests
            flags = int(r.cmd_flags.get_value())
            try:
                command = parse_command(flags, list(r.velocity.get_value()), list(r.position.get_value()),
                                        list(r.force.get_value()))
            except CommandRefused as error:
                self.refused += 1
                self.logger.warn(f'{self.manager.name}: refused command ({self.refused} so far): {error}')
                continue
            if command is None:
                self._set_running(False, 'released (cmdFlags -1)')
            elif not self.control.running:
                self.logger.warn(f'{self.manager.name}: thread stopped; cmdFlags {flags} ignored '
                                 '(start_activity first)')
            else:
                self.control.accept(command, now)
                self._publish_command(command)
        while self.status.get_next_request():
            element = list(self.status.requests.element.get_value())
            if element and element[0] == 0:
                self._set_running(True, 'start_activity')
                self.drive_status.requests.element.set_value([0])     # the drive's start_activity
                self.drive_status.publish_request()
            elif element and element[0] == THREAD_STOPPED:
                self._set_running(False, 'stopped by request')

    def _set_running(self, running: bool, why: str) -> None:
        if running != self.control.running:
            self.control.set_running(running)
            self.logger.notice(f'{self.manager.name}: thread {"started" if running else "stopped"}: {why}')

    def _take_sensors(self, now: float, pose: tuple[float, float, float] | None) -> None:
        while self.laser.get_next_info():
            self.laser_beams = _beams(self.laser.info)
        while self.sonar.get_next_info():
            self.sonar_beams = _beams(self.sonar.info)
        if self.laser.get_next_data() and self.laser_beams is not None:
            ranges = [float(r) for r in self.laser.data.ranges]
            stamp = self.laser.data.timestamp.get_seconds()
            self.control.set_laser(ranges, self.laser_beams.points(ranges), stamp, now, pose)
        if self.sonar.get_next_data() and self.sonar_beams is not None:
            ranges = np.asarray(self.sonar.data.ranges, dtype=float)
            points = self.sonar_beams.points(ranges)
            cones = np.full(len(points), self.sonar_beams.half_angle)
            self.control.set_sonar(points, cones, pose)
            self.sonar_at = now
        elif now - self.sonar_at > SONAR_FRESH_S:
            self.control.set_sonar(np.zeros((0, 2)), np.zeros(0), None)
        if self.drive_status.get_next_data():
            self.drive_data = list(self.drive_status.data.data)
            self.drive_element = list(self.drive_status.data.element)

    # -- outputs ---------------------------------------------------------------------------------
    def _write_drive(self, order: DriveOrder) -> None:
        req = self.drive.requests
        req.cmd_flags.set_value(order.cmd_flags)
        req.velocity.set_value(list(order.velocity))
        req.position.set_value(list(order.position))
        self.drive.publish_request()

    def _publish_command(self, command: AvoidCommand) -> None:
        data = self.commands.data
        data.cmd_flags = command.cmd_flags
        if command.kind.name == 'GOTO':
            data.position, data.velocity, data.force = list(command.goal), [command.max_tv, command.max_rv], [command.strength]
        else:
            data.position, data.velocity, data.force = [command.distance, command.heading], [command.tv, command.rv], []
        self.commands.publish_data()

    def _publish_status(self, now: float) -> None:
        value = self.control.status(self.drive_data, self.drive_element, self.refused)
        if value == self.sent_status and now - self.status_at < STATUS_PERIOD_S:
            return
        self.status.data.data, self.status.data.element = value
        self.status.publish_data()
        self.sent_status, self.status_at = value, now

    # -- one loop --------------------------------------------------------------------------------
    def step(self) -> None:
        now = time.monotonic()
        self._take_commands(now)
        pose = self.pose.pose()
        self._take_sensors(now, pose)
        order = self.control.step(now, pose)
        if order is not None:
            self._write_drive(order)
        failure = self.control.failure if self.control.laser_code == 7 else None
        if failure != self.failure:
            if failure is not None:
                self.logger.warn(f'{self.manager.name}: laser {failure}: robot stopped')
            self.failure = failure
        self._publish_status(now)

    def close(self) -> None:
        """Leave the drive stopped (idempotent)."""
        if self.control.running and self.control.command is not None:
            self._write_drive(DriveOrder(0, (0.0, 0.0)))


def _number(user: dict[str, str], letter: str) -> float | None:
    if letter not in user:
        return None
    try:
        value = float(user[letter])
    except ValueError:
        raise ValueError(f'-{letter} {user[letter]!r}: not a number') from None
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f'-{letter} {user[letter]!r}: must be a positive number')
    return value


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('avoidModule')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'b:l:r:S:').user
    try:
        radius, stale = _number(user, 'r'), _number(user, 'S')
    except ValueError as error:
        print(f'avoid_module: {error}', file=sys.stderr, flush=True)
        return 2
    field, guard = FieldSettings(), GuardLimits()
    if radius is not None:
        field, guard = FieldSettings(radius=radius), GuardLimits(radius=radius)
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    base, laser = user.get('b', 'PlutoBase'), user.get('l', 'PlutoLaser')
    module = AvoidModule(manager, logger, AvoidController(field, guard, stale), base=base, laser=laser)
    set_loop(manager, 0.0)
    logger.notice(f'{manager.name}: driving drive/command; laser {laser}, sonar {base}Sonar')
    return run_loop(manager, module.step, module.close)


if __name__ == '__main__':
    sys.exit(main())
