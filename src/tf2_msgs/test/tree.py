"""The transforms and QoS of the round-trip test, shared by the test and its peer process.

A REP-105 chain as Pluto will publish it: map -> odom -> base_link on /tf, and the laser's
mounting base_link -> laser on /tf_static.  The QoS are tf2_ros's: /tf reliable, volatile,
depth 100; /tf_static reliable, transient local, depth 1 (a late subscriber such as RViz still
gets the static transforms).
"""

from __future__ import annotations

import math

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Quaternion, Transform, TransformStamped, Vector3
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage

TF_QOS = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE,
                    durability=DurabilityPolicy.VOLATILE)
TF_STATIC_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                           durability=DurabilityPolicy.TRANSIENT_LOCAL)
STAMP = Time(sec=1_700_000_000, nanosec=123_456_789)


def _transform(parent: str, child: str, x: float, y: float, z: float,
               yaw: float) -> TransformStamped:
    message = TransformStamped()
    message.header.stamp = STAMP
    message.header.frame_id = parent
    message.child_frame_id = child
    message.transform = Transform(
        translation=Vector3(x=x, y=y, z=z),
        rotation=Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2)))
    return message


def dynamic() -> TFMessage:
    """What goes on /tf: map -> odom -> base_link."""
    return TFMessage(transforms=[_transform('map', 'odom', 1.5, -0.25, 0.0, 0.1),
                                 _transform('odom', 'base_link', 6.0, 7.5, 0.0, -1.2)])


def static() -> TFMessage:
    """What goes on /tf_static: the laser mounted on the base."""
    return TFMessage(transforms=[_transform('base_link', 'laser', 0.2, 0.0, 0.35, 0.0)])
