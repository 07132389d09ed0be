"""ros_inputs: any ROS 2 robot's standard topics in, the WURDE base and laser streams out.

A robot that has never heard of WURDE — a LaserScan, an Odometry, transforms on ``/tf_static``
and ``/tf``, a base that takes a Twist — becomes a base module and a laser module to the rest of
the suite: localModule, poseModule, slamModule and the drive → avoid → motion chain run on it as on
the simulated Pluto.  One module supplies both sets of streams, through the classes the dummies and
drivers use (:class:`~wurde_drivers.streams.base.BaseStreams`,
:class:`~wurde_drivers.streams.laser.LaserStreams`), so no consumer can tell.

``-b BASE`` and ``-s LASER`` name the streams (default PlutoBase and PlutoLaser), ``-n`` the
module; the robot's side is ROS 2 parameters (:mod:`.settings`).  No IMU is read: the
localModule's other rotation source is a DMU stream, which a ROS IMU's orientation is not.
Streams stop when their topics do (consumers judge staleness), and the module says so once
(:mod:`.topic_watch`).  Idle and the end stop the robot (one zero Twist).  docs/wurde-drivers.md
("ros_inputs.module") and config/README.md ("ros-robot") have the detail.
"""

from __future__ import annotations

import sys

from rclpy.duration import Duration
from wurde_core import CommsManager, Logger, RunState
from wurde_idl.errors import ConfigError

from ..module_setup import exit_on_config_error, run_loop, set_loop
from .base_input import BaseInput
from .laser_input import LaserInput
from .robot_topics import RobotTopics
from .settings import read_settings

__all__ = ['main']

#: Loop sleep: messages are taken every turn (a scan comes every 25-100 ms on most lasers).
SLEEP_S = 0.01
#: Longest wait for the robot's base to acknowledge the last Twist when the module ends.
STOP_ACK_S = 0.5
HELP = ('  -b BASE   stream name of the base (<BASE>Motion, <BASE>Drive, ...; default PlutoBase)\n'
        '  -s LASER  stream name of the laser (<LASER>, <LASER>/RWI, <LASER>/Timing; default '
        'PlutoLaser)\n'
        '  ROS parameters (--ros-args -p NAME:=VALUE): scan_topic, odom_topic, cmd_vel_topic, '
        'base_frame,\n  laser_frame, max_tv, max_rv, tv_accel, rv_accel, wheel_base, '
        'command_timeout, cmd_rate,\n  silent_after, max_held_scans (wurde_drivers.ros_inputs.settings; '
        'config/README.md, "ros-robot")')


class RosInputs:
    """The module's work per loop turn: odometry, transforms and scans in, commands out."""

    def __init__(self, manager: CommsManager, base: BaseInput, laser: LaserInput) -> None:
        self.manager, self.base, self.laser = manager, base, laser

    def now(self) -> float:
        return self.manager.now().get_seconds()

    def step(self) -> None:
        self.base.take_odometry(self.now)
        self.laser.step(self.base.frame, self.now)
        self.base.take_commands()
        self.base.watch.check()
        self.laser.watch.check()

    def close(self) -> None:
        """Stop the robot if we moved it, and let the Twist reach its base (bounded)."""
        self.base.stop()
        self.base.topics.cmd_vel.wait_for_all_acked(Duration(seconds=STOP_ACK_S))


def main(argv: list[str] | None = None) -> int:
    """The ``ros_inputs`` program: a ROS 2 robot's topics as a base module and a laser module.

    :param argv: the command line, program name first (ROS arguments after ``--ros-args``); None:
        ``sys.argv``.
    :returns: the exit status (2 for a bad parameter, with ``ros_inputs: parameter NAME: reason`` on
        stderr).
    """
    argv = list(sys.argv if argv is None else argv)
    manager = CommsManager('ros_inputs')
    manager.set_help_string(HELP)
    user = manager.parse_options(argv, 'b:s:').user
    base_name, laser_name = user.get('b', 'PlutoBase'), user.get('s', 'PlutoLaser')
    logger = Logger(manager.name)
    manager.register_supplier(logger)          # the node exists from here on
    try:
        settings = read_settings(manager.node)
        topics = RobotTopics(manager.node, settings, base=base_name, laser=laser_name)
    except ConfigError as error:
        manager.clean_up()
        return exit_on_config_error(argv[0], error)
    base = BaseInput(base_name, settings, topics, logger)
    laser = LaserInput(laser_name, settings, topics, logger)
    base.streams.register(manager)
    laser.streams.register(manager)
    set_loop(manager, SLEEP_S)
    base.streams.publish_all_info()
    runner = RosInputs(manager, base, laser)
    manager.on_state(RunState.IDLE, base.stop)
    logger.notice(f'{manager.name}: {topics.odom_topic} -> {base_name}Motion, {topics.scan_topic} -> '
                  f'{laser_name}, {base_name}Drive/Command -> {topics.cmd_vel_topic}')
    return run_loop(manager, runner.step, runner.close)


if __name__ == '__main__':
    sys.exit(main())
