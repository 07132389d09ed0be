"""The robot's odometry in, the chain's commands out: the base streams of ``ros_inputs``.

``nav_msgs/Odometry`` becomes ``<BASE>Motion`` (Egomotion: the pose x, y, yaw in the odometry's
frame, tv and rv from its twist, stamped with its header), through the same
:class:`~wurde_drivers.streams.base.BaseStreams` as the dummy base and the rFLEX driver, so the
localModule and the chain cannot tell them apart.  The base is a differential one (RobotDrive on
``<BASE>Drive``, SynchroDrive on its typed view), since a Twist is what a ROS base takes.

Commands come as the other bases' do (``<BASE>Drive`` and ``<BASE>Command`` requests, a Twist on
``<BASE>/cmd_vel``) into BaseStreams' watchdog, and whatever it decides goes to the robot as a
``geometry_msgs/Twist`` on its cmd_vel: every command that moves the robot, and one stop when it
is to stop — a zero command, the watchdog's stop when the commands stop coming, the module going
Idle or ending.  While the robot is to move, the last command is sent again every
``1 / cmd_rate`` s, since ROS base controllers stop a robot whose cmd_vel falls silent.  A robot
we stopped gets no further zero Twists (the driveModule writes its stop every cycle), so that
another program (a teleop) may drive it while the chain does not.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

from wurde_core import Logger

from ..streams.base import BaseLimits, BaseStreams
from .robot_topics import RobotTopics, seconds
from .settings import Settings
from .topic_watch import TopicWatch

__all__ = ['BaseInput', 'yaw_of']


def yaw_of(q: Any) -> float:
    """The heading (rotation about z) of a ``geometry_msgs/Quaternion``."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class BaseInput:
    """Odometry → ``<BASE>Motion``; BaseStreams' commands → Twist."""

    def __init__(self, name: str, settings: Settings, topics: RobotTopics, logger: Logger) -> None:
        self.settings, self.topics, self.logger = settings, topics, logger
        limits = BaseLimits(settings.max_tv, settings.max_rv, settings.tv_accel, settings.rv_accel,
                            wheel_base=settings.wheel_base)
        self.streams = BaseStreams(name, synchro=False, limits=limits,
                                   command_timeout=settings.command_timeout, logger=logger)
        self.watch = TopicWatch(f'Odometry on {topics.odom_topic}', settings.silent_after,
                                lambda text: logger.warn(f'{name}: {text}'),
                                lambda: topics.publishers(topics.odom_topic))
        #: The robot's body frame: the parameter, else the odometry's child frame.
        self.frame = settings.base_frame
        self.sent: tuple[float, float] | None = None
        self.sent_at = -math.inf
        self._last: tuple[float, float] | None = None     # (stamp, tv) of the last odometry
        self._told: set[str] = set()

    def _once(self, key: str, text: str) -> None:
        if key not in self._told:
            self._told.add(key)
            self.logger.warn(f'{self.streams.name}: {text}')

    # -- odometry -------------------------------------------------------------------------------
    def take_odometry(self, now: Callable[[], float]) -> int:
        """Publish every Odometry that arrived; ``now()`` stamps one whose header has none."""
        count = 0
        for message in self.topics.odometry():
            self.watch.heard()
            count += 1
            if not self.settings.base_frame:
                child = message.child_frame_id.lstrip('/')
                if child:
                    self.frame = child
                else:
                    self._once('child', f'Odometry on {self.topics.odom_topic} names no '
                               'child_frame_id: set the parameter base_frame')
            stamp = seconds(message.header.stamp)
            if stamp == 0.0:
                self._once('stamp', f'Odometry on {self.topics.odom_topic} has no stamp: '
                           'stamped on arrival')
                stamp = now()
            pose, twist = message.pose.pose, message.twist.twist
            values = (pose.position.x, pose.position.y, yaw_of(pose.orientation), twist.linear.x,
                      twist.angular.z)
            if not all(math.isfinite(v) for v in values):
                self._once('finite', f'Odometry on {self.topics.odom_topic} with values that are '
                           'not finite: left out')
                continue
            x, y, theta, tv, rv = values
            last, self._last = self._last, (stamp, tv)
            acceleration = (tv - last[1]) / (stamp - last[0]) if last and stamp > last[0] else 0.0
            self.streams.publish_motion(x, y, theta, tv, rv, acceleration, stamp)
        return count

    # -- commands -------------------------------------------------------------------------------
    def take_commands(self) -> None:
        """Send what BaseStreams decided, and the moving command again when it is due."""
        now = time.monotonic()
        command = self.streams.take_command(now)
        if command is not None:
            if self.moving or (command.tv, command.rv) != (0.0, 0.0):
                self._send(command.tv, command.rv, now)
        elif self.moving and now - self.sent_at >= 1.0 / self.settings.cmd_rate:
            assert self.sent is not None
            self._send(*self.sent, now)

    @property
    def moving(self) -> bool:
        """Whether the last Twist sent moves the robot."""
        return self.sent is not None and self.sent != (0.0, 0.0)

    def stop(self) -> None:
        """Stop the robot now (Idle, the end): one zero Twist, if the robot was moving by us."""
        command = self.streams.stop()
        if self.moving:
            self._send(command.tv, command.rv, time.monotonic())

    def _send(self, tv: float, rv: float, now: float) -> None:
        self.topics.send(tv, rv)
        self.sent, self.sent_at = (tv, rv), now
