"""The localization on standard ROS 2 topics, for a stock RViz or Foxglove (REP-105).

================= ============================================ =====================================
topic             type                                         what
================= ============================================ =====================================
``odom``          nav_msgs/Odometry                            stream (0): ``base_link`` in ``odom``
``pose``          geometry_msgs/PoseWithCovarianceStamped      stream (3) in ``map``
``tf``            tf2_msgs/TFMessage                           map → odom (the adjustment) and
                                                               odom → base_link (dead reckoning)
================= ============================================ =====================================

The sensors' mountings (``base_link`` → the laser's frame and the others) are not published here:
each device module publishes its own on ``tf_static`` from its config (one home per transform,
:mod:`wurde_drivers.ros_std_frames`).

All three are relative names, so they follow the node's namespace (``/tf`` for a robot started
plainly, ``/robot1/tf`` in ``/robot1``: the namespaced-TF convention of multi-robot ROS 2);
covariances are the streams' (x, y, theta) ones placed in the 6x6 ROS layout (z, roll and pitch
marked unknown-large).  Each is built and sent only while something subscribes to it
(:func:`wurde_core.ros_adaptor.watched`, issue 39).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped
from nav_msgs.msg import Odometry
from rclpy.qos import QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage
from wurde_core.ros_adaptor import watched
from wurde_core.ros_messages import quaternion, set_stamp

__all__ = ['LocalizationPublisher', 'covariance6']

_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
#: Variance given to the axes the localization does not estimate (z, roll, pitch): "unknown".
UNKNOWN_VARIANCE = 1e6


def covariance6(cov3: np.ndarray) -> np.ndarray:
    """The 6x6 row-major ROS covariance (x, y, z, roll, pitch, yaw) of an (x, y, theta) one."""
    full = np.zeros((6, 6))
    full[np.ix_(_XY_YAW, _XY_YAW)] = cov3
    full[_UNKNOWN, _UNKNOWN] = UNKNOWN_VARIANCE
    return full.reshape(-1)


_XY_YAW = [0, 1, 5]
_UNKNOWN = [2, 3, 4]


def _set_transform(t: TransformStamped, pose: Sequence[float] | np.ndarray, stamp: float) -> None:
    set_stamp(t, stamp)
    translation, rotation = t.transform.translation, t.transform.rotation
    translation.x, translation.y, translation.z = float(pose[0]), float(pose[1]), 0.0
    rotation.x, rotation.y, rotation.z, rotation.w = quaternion(float(pose[2]))


def _fill(message: Any, with_covariance: Any, pose: Sequence[float] | np.ndarray, cov3: np.ndarray,
          stamp: float) -> None:
    """Stamp ``message`` and set its PoseWithCovariance ``with_covariance`` from (x, y, theta)."""
    set_stamp(message, stamp)
    p = with_covariance.pose
    p.position.x, p.position.y = float(pose[0]), float(pose[1])
    p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w = quaternion(float(pose[2]))
    with_covariance.covariance = covariance6(cov3)


def _transform(parent: str, child: str) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    return t


class LocalizationPublisher:
    """Publishes odom, pose and TF for the localModule on ``node``; the messages are built once
    and refilled (building ROS messages in Python costs more than publishing them)."""

    def __init__(self, node: Any) -> None:
        self.odom = node.create_publisher(Odometry, 'odom', _QOS)
        self.pose = node.create_publisher(PoseWithCovarianceStamped, 'pose', _QOS)
        self.tf = node.create_publisher(TFMessage, 'tf', _QOS)
        self._odom = Odometry()
        self._odom.header.frame_id, self._odom.child_frame_id = 'odom', 'base_link'
        self._pose = PoseWithCovarianceStamped()
        self._pose.header.frame_id = 'map'
        self._tf = TFMessage(transforms=[_transform('map', 'odom'), _transform('odom', 'base_link')])

    def publish(self, stamp: float, dead_reckoning: np.ndarray, dr_cov: np.ndarray, tv: float, rv: float,
                adjustment: np.ndarray, pose: np.ndarray, pose_cov: np.ndarray) -> None:
        if watched(self.odom):
            odom = self._odom
            _fill(odom, odom.pose, dead_reckoning, dr_cov, stamp)
            odom.twist.twist.linear.x, odom.twist.twist.angular.z = float(tv), float(rv)
            self.odom.publish(odom)
        if watched(self.pose):
            _fill(self._pose, self._pose.pose, pose, pose_cov, stamp)
            self.pose.publish(self._pose)
        if watched(self.tf):
            to_odom, to_base = self._tf.transforms
            _set_transform(to_odom, adjustment, stamp)
            _set_transform(to_base, dead_reckoning, stamp)
            self.tf.publish(self._tf)
