"""The standard ROS 2 mirrors ``carmen_log play`` publishes beside its WURDE streams.

The same topics and frames as the base and laser drivers and dummies give (wurde_drivers'
``ros_std``, ``ros_std_frames``: pluto_nav may not import them, so the few lines are here):

================== ===================== ========================================================
topic              type                  what
================== ===================== ========================================================
``/<LASER>/scan``  sensor_msgs/LaserScan the scan, frame ``<LASER>`` (``/`` → ``_``); angles are
                                         the robot's bearings (the mount's yaw is in the angles,
                                         as a :class:`Fan` laser's), no-return ``inf``
``/<BASE>/odom``   nav_msgs/Odometry     the odometry, ``odom`` → ``base_link``
``/tf_static``     tf2_msgs/TFMessage    ``base_link`` → ``<LASER>`` at the mount (no yaw), latched
``/tf``            tf2_msgs/TFMessage    ``odom`` → ``base_link`` per odometry record, only with
                                         ``-t``: the localModule publishes that transform itself
================== ===================== ========================================================

All names are relative, so they follow the node's namespace.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage
from wurde_core.naming import stream_segment_path
from wurde_core.ros_messages import quaternion, set_stamp

from .logs.records import OdometryRecord

__all__ = ['PlayMirrors']

_STATIC_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)


def _transform(parent: str, child: str, x: float, y: float, z: float, yaw: float, stamp: float) -> TransformStamped:
    t = TransformStamped()
    set_stamp(t, stamp)
    t.header.frame_id, t.child_frame_id = parent, child
    tr, rot = t.transform.translation, t.transform.rotation
    tr.x, tr.y, tr.z = float(x), float(y), float(z)
    rot.x, rot.y, rot.z, rot.w = quaternion(float(yaw))
    return t


class PlayMirrors:
    """Publishers of the mirrors on ``node`` for base ``base`` and laser ``laser``; ``depth`` is
    their history's (1 where every message waits for its acknowledgements)."""

    def __init__(self, node: Any, *, base: str, laser: str, tf: bool, depth: int = 10) -> None:
        qos = QoSProfile(depth=depth, reliability=ReliabilityPolicy.RELIABLE)
        self.frame = laser.replace('/', '_')
        self.scan = node.create_publisher(LaserScan, f'{stream_segment_path(laser)}/scan', qos)
        self.odom = node.create_publisher(Odometry, f'{stream_segment_path(base)}/odom', qos)
        self.static = node.create_publisher(TFMessage, 'tf_static', _STATIC_QOS)
        self.tf = node.create_publisher(TFMessage, 'tf', qos) if tf else None
        self._odom = Odometry()
        self._odom.header.frame_id, self._odom.child_frame_id = 'odom', 'base_link'

    @property
    def publishers(self) -> list[Any]:
        return [p for p in (self.scan, self.odom, self.static, self.tf) if p is not None]

    def announce(self, x: float, y: float, z: float) -> None:
        """``base_link`` → the laser's frame at its mounting point."""
        self.static.publish(TFMessage(transforms=[_transform('base_link', self.frame, x, y, z, 0.0, time.time())]))

    def publish_scan(self, ranges: Sequence[float], stamp: float, *, first: float, step: float,
                     max_range: float) -> list[Any]:
        msg = LaserScan()
        set_stamp(msg, stamp)
        msg.header.frame_id = self.frame
        msg.angle_min = float(first)
        msg.angle_max = float(first + step * max(len(ranges) - 1, 0))
        msg.angle_increment = float(step)
        msg.range_min = 0.0
        msg.range_max = float(max_range)
        msg.ranges = [float(r) for r in ranges]
        self.scan.publish(msg)
        return [self.scan]

    def publish_odometry(self, record: OdometryRecord) -> list[Any]:
        msg = self._odom
        set_stamp(msg, record.stamp)
        pose = msg.pose.pose
        pose.position.x, pose.position.y = float(record.x), float(record.y)
        pose.orientation.z, pose.orientation.w = math.sin(record.theta / 2), math.cos(record.theta / 2)
        msg.twist.twist.linear.x, msg.twist.twist.angular.z = float(record.tv), float(record.rv)
        self.odom.publish(msg)
        if self.tf is None:
            return [self.odom]
        self.tf.publish(TFMessage(transforms=[_transform('odom', 'base_link', record.x, record.y, 0.0,
                                                         record.theta, record.stamp)]))
        return [self.odom, self.tf]
