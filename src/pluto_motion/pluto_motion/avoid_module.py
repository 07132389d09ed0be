"""avoid_module: Pluto's avoidModule (Pluto 6.2), the second link of the movement chain (Pluto 4).

It reads its command interface ``avoidance/command`` (ActuatorState requests, cmdFlags = 10*A +
T: :mod:`pluto_motion.avoid_command`) and writes the driveModule's, ``drive/command``, "after
possibly modifying the command" (Pluto 4); the drive's ``drive/status`` comes back up as
``avoidance/status``.  It reads the laser (``-L``, default PlutoLaser), the base's sonar
``<base>Sonar`` and the pose (:class:`pluto_motion.pose_source.PoseSource`: Localization/Pose, else
Dead-Reckoning, else the base odometry, each fall-back warned once).  The control (goto, wall
follow, laser and sonar protection) is :mod:`pluto_motion.avoid_control`.

docs/movement.md ("Movement", avoidModule) has the tables of ``avoidance/command`` and
``avoidance/status`` and the options.

Before changing it: each laser scan and sonar reading is placed at the pose of its stamp in a
frame that never jumps (:meth:`~pluto_motion.pose_source.PoseSource.frame`) and moved with the
robot in it, so that a correction of Localization/Pose is not taken for motion.  A laser that
fails or falls silent stops the robot (fail closed).  The loop runs on every laser scan (a
trigger), every command and at least every :data:`LOOP_S` seconds, so a scan's drive command
goes out as soon as it is computed.
"""

from __future__ import annotations

import math
import sys
import time
from typing import Any

import numpy as np

from wurde_core import CommsManager, Logger, Trigger
from wurde_core.interfaces import ActuatorState, FVectorState, RangeFinder
from wurde_core.module_loop import run_loop, set_loop
from wurde_core.parameters import TunedSettings

from . import drive_command
from .avoid_command import COMMAND, STATUS, AvoidCommand, parse_command
from .avoid_control import GOTO_REACHED, GOTO_STUCK, AvoidController, DriveOrder
from .chain_link import ChainLink
from .goto_field import FieldSettings
from .laser_guard import LASER_FATAL, GuardLimits
from .pose_source import PoseSource
from .scan_points import Beams

__all__ = ['COMMAND', 'STATUS', 'AvoidModule', 'Every', 'main']

#: Longest time between two loops (s) when no scan or command wakes the module.
LOOP_S = 0.05
#: A sonar reading older than this (s) is left out of the goto's field.
SONAR_FRESH_S = 1.0
#: Tunables (ROS 2 parameters of the node, ``ros2 param set /avoidModule goto.reach_goal 0.3``):
#: the goto's and the laser guard's distances, what each means and its range.
GOTO_TUNABLES: dict[str, tuple[str, float | None, float | None]] = {
    'reach_goal': ('a goto has reached its goal within this distance, m', 0.02, 5.0),
    'goal_slow': ('a goto slows down within this distance of its goal, m', 0.0, 10.0),
    'reach': ('obstacles nearer than this push the goto away, m (Pluto 6.2: 3)', 0.5, 10.0),
    'stuck_s': ('a goto with no progress for this long is stuck, s', 1.0, 600.0)}
LASER_TUNABLES: dict[str, tuple[str, float | None, float | None]] = {
    'stop': ('laser protection stops at this free distance, m', 0.0, 2.0),
    'slow': ('laser protection slows from this free distance, m', 0.1, 10.0)}
HELP = ('  -b BASE      the base module (default PlutoBase): reads <BASE>Sonar, <BASE>Motion\n'
        '  -L LASER     the laser (default PlutoLaser): RangeFinder stream LASER\n'
        '  -R RADIUS    the robot\'s radius, m (0.35)\n'
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


def _beams(info: Any, count: int) -> Beams:
    """The beams of a RangeFinder whose readings have ``count`` values: its sensor poses, or a
    uniform fan (the info gives no count: the readings do)."""
    positions = list(info.sensor_positions.get_value())
    half = float(info.half_angle.get_value())
    if positions:
        return Beams.ring([(p.x(), p.y(), p.theta()) for p in positions], half)
    return Beams.fan(count, first=float(info.theta_offset.get_value()),
                     step=float(info.theta_separation.get_value()),
                     x=float(info.x_offset.get_value()),
                     y=float(info.y_offset.get_value()),
                     half_angle=half)


class AvoidModule:
    """The avoidModule's streams around an :class:`AvoidController`."""

    def __init__(self, manager: CommsManager, logger: Logger, control: AvoidController, *,
                 base: str, laser: str) -> None:
        self.manager, self.logger, self.control = manager, logger, control
        self.tuned_field = TunedSettings(manager, control.field, GOTO_TUNABLES, 'goto.')
        self.tuned_guard = TunedSettings(manager, control.guard.limits, LASER_TUNABLES, 'laser.')
        self.link = ChainLink(manager, logger, COMMAND, STATUS, parse=parse_command, accept=self._accept,
                              set_running=control.set_running, running=lambda: control.running)
        self.drive = ActuatorState(drive_command.COMMAND)
        self.drive_status = FVectorState(drive_command.STATUS)
        self.laser = RangeFinder(laser)
        self.sonar = RangeFinder(f'{base}Sonar')
        for obj in (self.drive, self.drive_status, self.laser, self.sonar):
            manager.register_consumer(obj)
        for trigger in (Trigger(self.laser), Trigger(self.link.commands), Trigger(self.link.status), Every(LOOP_S)):
            manager.register_trigger(trigger)
        #: The source readings are placed and moved in (:meth:`PoseSource.frame`).
        self.frame_source: str | None = None
        self.pose = PoseSource(manager, base, lambda text: logger.warn(f'{manager.name}: {text}'),
                               user='the goto and the regulator steer')
        self.laser_info = self.sonar_info = False
        self.laser_beams: Beams | None = None
        self.sonar_beams: Beams | None = None
        self.sonar_at = -math.inf
        self.drive_data: list[float] = []
        self.drive_element: list[int] = []
        self.laser_dead = False
        self.warned_stamps = False

    # -- inputs ----------------------------------------------------------------------------------
    def _accept(self, command: AvoidCommand, now: float) -> None:
        self.control.accept(command, now)
        self._publish_command(command)

    def _take_commands(self, now: float) -> None:
        if 0 in self.link.take_commands(now):
            self.drive_status.requests.element.set_value([0])     # the drive's start_activity
            self.drive_status.publish_request()

    def _take_sensors(self, now: float) -> None:
        while self.laser.get_next_info():
            self.laser_info, self.laser_beams = True, None
        while self.sonar.get_next_info():
            self.sonar_info, self.sonar_beams = True, None
        if self.laser.get_next_data() and self.laser_info:
            ranges = [float(r) for r in self.laser.data.ranges]
            if self.laser_beams is None or len(self.laser_beams) != len(ranges):
                self.laser_beams = _beams(self.laser.info, len(ranges))
            stamp = self.laser.data.timestamp.get_seconds()
            beams = self.laser_beams
            view = (float(beams.x[0]), float(beams.y[0]), float(beams.theta[0]), float(beams.theta[-1])) \
                if len(beams) else None
            self.control.set_laser(ranges, beams.points(ranges), stamp, now, self._taken_at(stamp), view)
        if self.sonar.get_next_data() and self.sonar_info:
            sonar_ranges = np.asarray(self.sonar.data.ranges, dtype=float)
            if self.sonar_beams is None or len(self.sonar_beams) != len(sonar_ranges):
                self.sonar_beams = _beams(self.sonar.info, len(sonar_ranges))
            points = self.sonar_beams.points(sonar_ranges)
            cones = np.full(len(points), self.sonar_beams.half_angle)
            self.control.set_sonar(points, cones, self._taken_at(self.sonar.data.timestamp.get_seconds()))
            self.sonar_at = now
        elif now - self.sonar_at > SONAR_FRESH_S:
            self.control.set_sonar(np.zeros((0, 2)), np.zeros(0), None)
        if self.drive_status.get_next_data():
            self.drive_data = list(self.drive_status.data.data)
            self.control.speed = self.drive_data[0] if self.drive_data else 0.0
            self.drive_element = list(self.drive_status.data.element)

    def _taken_at(self, stamp: float) -> tuple[float, float, float] | None:
        """The pose in the readings' frame (:meth:`PoseSource.frame`) a reading stamped ``stamp``
        was taken at (a SICK scan is 0.2 s old when it arrives at 38400 baud, 0.77 s at 9600:
        :mod:`wurde_drivers.sick.facts`); the latest pose when the poses kept do not reach the
        stamp (a reading on another clock is said, once); None without a frame."""
        frame = self.frame_source
        if frame is None:
            return None
        taken = self.pose.pose_at(frame, stamp)
        if taken is not None:
            return taken
        if not self.warned_stamps and self.pose.beyond(frame, stamp):
            self.logger.warn(f'{self.manager.name}: a reading stamped {stamp:.3f} is outside the stamps of '
                             f'{frame}: readings are placed at the pose of their arrival')
            self.warned_stamps = True
        return self.pose.poses[frame]

    # -- outputs ---------------------------------------------------------------------------------
    def _write_drive(self, order: DriveOrder) -> None:
        req = self.drive.requests
        req.cmd_flags.set_value(order.cmd_flags)
        req.velocity.set_value(list(order.velocity))
        req.position.set_value(list(order.position))
        self.drive.publish_request()

    def _publish_command(self, command: AvoidCommand) -> None:
        data = self.link.commands.data
        data.cmd_flags = command.cmd_flags
        if command.kind.name == 'GOTO':
            data.position, data.velocity = list(command.goal), [command.max_tv, command.max_rv]
            data.force = [command.strength]
        else:
            data.position, data.velocity, data.force = [command.distance, command.heading], [command.tv, command.rv], []
        self.link.commands.publish_data()

    # -- one loop --------------------------------------------------------------------------------
    def step(self) -> None:
        self.control.tune(self.tuned_field.current(), self.tuned_guard.current())
        now = time.monotonic()
        self._take_commands(now)
        pose = self.pose.pose()
        frame = self.pose.frame()
        if frame != self.frame_source:
            # The readings' frame changed (the base odometry, then Dead-Reckoning): the readings
            # kept are not moved by the difference of two frames (that put a wall inside the robot
            # and ended a goto as stuck at its start).
            self.frame_source = frame
            self.control.forget_poses()
        self._take_sensors(now)
        before = self.control.goto_code
        order = self.control.step(now, pose, None if frame is None else self.pose.poses[frame])
        if self.control.goto_code != before and self.control.goto_code == GOTO_STUCK:
            self.logger.warn(f'{self.manager.name}: {self.control.stuck_reason}')
        elif self.control.goto_code != before and self.control.goto_code == GOTO_REACHED:
            self.logger.notice(f'{self.manager.name}: goto point reached')
        if order is not None:
            self._write_drive(order)
        dead = self.control.laser_code == LASER_FATAL
        if dead and not self.laser_dead:
            self.logger.warn(f'{self.manager.name}: laser {self.control.failure}: robot stopped')
        elif self.laser_dead and not dead:
            self.logger.notice(f'{self.manager.name}: laser stop over')
        self.laser_dead = dead
        data, element = self.control.status(self.drive_data, self.drive_element, self.link.refused)
        self.link.publish_status(data, element, now)

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
    user = manager.parse_options(argv, 'b:L:R:S:').user
    try:
        radius, stale = _number(user, 'R'), _number(user, 'S')
    except ValueError as error:
        print(f'avoid_module: {error}', file=sys.stderr, flush=True)
        return 2
    field, guard = FieldSettings(), GuardLimits()
    if radius is not None:
        field, guard = FieldSettings(radius=radius), GuardLimits(radius=radius)
    logger = Logger(manager.name)
    manager.register_supplier(logger)
    base, laser = user.get('b', 'PlutoBase'), user.get('L', 'PlutoLaser')
    module = AvoidModule(manager, logger, AvoidController(field, guard, stale), base=base, laser=laser)
    set_loop(manager, 0.0)
    logger.notice(f'{manager.name}: driving drive/command; laser {laser}, sonar {base}Sonar')
    return run_loop(manager, module.step, module.close)


if __name__ == '__main__':
    sys.exit(main())
