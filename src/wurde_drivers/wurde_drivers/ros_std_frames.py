"""Frame names and the static transforms of a device module (REP-105, ``/tf_static``).

**The frame rule.** A device's frame is its stream's name with ``/`` replaced by ``_``
(:func:`frame_of`): the laser ``PlutoLaser`` is frame ``PlutoLaser``, the DMU ``PlutoDMU``, the
GPS antenna ``PlutoGPS``, a pan/tilt unit's base ``PlutoWrist``. A bank of sensors on one stream
numbers its members from 0 in the stream's order: sonar ``i`` of ``PlutoBaseSonar`` is frame
``PlutoBaseSonar_i``, bumper ``i`` of ``PlutoBaseBumpers`` is ``PlutoBaseBumpers_i``
(:func:`member_frame`). Every sensor frame hangs off ``base_link``.

**One home per transform.** Each module publishes the mountings of its own devices, from its
config, as one ``tf2_msgs/TFMessage`` on ``tf_static`` (relative like every standard topic:
``/tf_static`` for a robot started plainly, ``/robot1/tf_static`` in ``/robot1``) with tf2_ros's
QoS (reliable, transient local, depth 1): a subscriber that comes later still gets them, as from a
``StaticTransformBroadcaster``, which :class:`StaticFrames` imitates (every call republishes
the whole set, since depth 1 keeps only the last message of each publisher).
"""

from __future__ import annotations

import time
from collections.abc import Iterable
from typing import Any

from geometry_msgs.msg import TransformStamped
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage
from wurde_core.ros_messages import quaternion, set_stamp

from .mounting import Mounting

__all__ = ['BASE_FRAME', 'STATIC_QOS', 'StaticFrames', 'frame_of', 'member_frame']

#: The robot's body frame (REP-105); every mounting is relative to it.
BASE_FRAME = 'base_link'
#: tf2_ros's static QoS: late subscribers get the transforms.
STATIC_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                        durability=DurabilityPolicy.TRANSIENT_LOCAL)


def frame_of(stream: str) -> str:
    """The frame of the device on ``stream``: the name with ``/`` replaced by ``_``."""
    return stream.replace('/', '_')


def member_frame(stream: str, index: int) -> str:
    """The frame of sensor ``index`` (from 0) of the bank on ``stream``."""
    return f'{frame_of(stream)}_{index}'


class StaticFrames:
    """The static transforms of one module's node; :meth:`set` adds or replaces some and sends all.

    :param node: the module's node (``manager.node``).
    """

    def __init__(self, node: Any) -> None:
        self.publisher = node.create_publisher(TFMessage, 'tf_static', STATIC_QOS)
        self.transforms: dict[str, TransformStamped] = {}

    def set(self, mountings: Iterable[tuple[str, Mounting]]) -> None:
        """``base_link`` → each ``(frame, mounting)``; then the whole set is published again."""
        now = time.time()
        for frame, mount in mountings:
            t = TransformStamped()
            set_stamp(t, now)
            t.header.frame_id, t.child_frame_id = BASE_FRAME, frame
            tr, rot = t.transform.translation, t.transform.rotation
            tr.x, tr.y, tr.z = float(mount.x), float(mount.y), float(mount.z)
            rot.x, rot.y, rot.z, rot.w = quaternion(float(mount.yaw))
            self.transforms[frame] = t
        self.publisher.publish(TFMessage(transforms=list(self.transforms.values())))
