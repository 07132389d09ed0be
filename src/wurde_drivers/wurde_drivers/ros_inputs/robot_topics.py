"""The robot's own topics, as ``ros_inputs`` reads and writes them (QoS and names).

Sensor data from real drivers is often best effort: the scan, the odometry and ``/tf`` are read
best effort, which matches reliable and best-effort publishers alike.  ``/tf_static`` is read as
tf2 does (reliable, transient local), so the mounts a robot published before ``ros_inputs``
started arrive too.  The Twist goes out reliable, which every subscriber matches.

Messages are taken by the module's loop (no executor), as the WURDE channels are.  A topic that
would bring our own messages back (the robot's cmd_vel named as the base's standard
``<BASE>/cmd_vel``, which the base streams read) is refused at start.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage
from wurde_core.ros_adaptor import polled, take
from wurde_idl.errors import ConfigError

from ..ros_std import std_topic
from .settings import Settings

__all__ = ['RobotTopics', 'seconds']

SENSOR_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=20,
                        reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)
TF_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                    reliability=ReliabilityPolicy.BEST_EFFORT, durability=DurabilityPolicy.VOLATILE)
TF_STATIC_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                           reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
COMMAND_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                         reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)


def seconds(stamp: Any) -> float:
    """A ``builtin_interfaces/Time`` in seconds."""
    return stamp.sec + stamp.nanosec * 1e-9


def _resolve(node: Any, parameter: str, name: str) -> str:
    try:
        return str(node.resolve_topic_name(name))
    except Exception as error:  # rclpy raises several types for a bad name
        raise ConfigError(f'parameter {parameter}', None, f'{name!r} is not a valid topic name '
                          f'({error})') from error


class RobotTopics:
    """The subscriptions to the robot's scan, odometry and transforms, and its cmd_vel.

    :raises ConfigError: a topic name that is not valid, or one that is our own mirror.
    """

    def __init__(self, node: Any, settings: Settings, *, base: str, laser: str) -> None:
        self.node = node
        self.scan_topic = _resolve(node, 'scan_topic', settings.scan_topic)
        self.odom_topic = _resolve(node, 'odom_topic', settings.odom_topic)
        self.cmd_vel_topic = _resolve(node, 'cmd_vel_topic', settings.cmd_vel_topic)
        ours = {self.scan_topic: (std_topic(laser, 'scan'), 'scan_topic'),
                self.odom_topic: (std_topic(base, 'odom'), 'odom_topic'),
                self.cmd_vel_topic: (std_topic(base, 'cmd_vel'), 'cmd_vel_topic')}
        for topic, (mirror, parameter) in ours.items():
            if topic == _resolve(node, parameter, mirror):
                raise ConfigError(f'parameter {parameter}', None, f'{topic} is this module\'s own '
                                  'standard topic: what it publishes (or reads) there would come '
                                  'back in; name the robot\'s topic')
        self.scan = node.create_subscription(LaserScan, self.scan_topic, polled, SENSOR_QOS)
        self.odom = node.create_subscription(Odometry, self.odom_topic, polled, SENSOR_QOS)
        self.tf = node.create_subscription(TFMessage, 'tf', polled, TF_QOS)
        self.tf_static = node.create_subscription(TFMessage, 'tf_static', polled, TF_STATIC_QOS)
        self.cmd_vel = node.create_publisher(Twist, self.cmd_vel_topic, COMMAND_QOS)

    def scans(self) -> Iterator[LaserScan]:
        return take(self.scan)

    def odometry(self) -> Iterator[Odometry]:
        return take(self.odom)

    def transforms(self) -> Iterator[tuple[Any, bool]]:
        """Every TransformStamped that arrived, with whether it came on ``/tf_static``."""
        for subscription, static in ((self.tf_static, True), (self.tf, False)):
            for message in take(subscription):
                for transform in message.transforms:
                    yield transform, static

    def send(self, tv: float, rv: float) -> None:
        twist = Twist()
        twist.linear.x, twist.angular.z = float(tv), float(rv)
        self.cmd_vel.publish(twist)

    def publishers(self, topic: str) -> list[str]:
        """The nodes the graph shows publishing on ``topic`` (for :mod:`.topic_watch`)."""
        return sorted(f'{info.node_namespace.rstrip("/")}/{info.node_name}'
                      for info in self.node.get_publishers_info_by_topic(topic))
