"""The localModule's standard topics (odom, pose, tf: :mod:`pluto_nav.ros_std`) are built and sent
only while something subscribes to each (issue 39), as the device modules' mirrors are; a reader
that comes gets the next poses, whole.  Real rclpy, one process."""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import pytest
import rclpy
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from tf2_msgs.msg import TFMessage
from wurde_core.ros_adaptor import watched

from pluto_nav.ros_std import UNKNOWN_VARIANCE, LocalizationPublisher


def _until(executor: SingleThreadedExecutor, predicate: Any, what: str, timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, f'no {what} within {timeout} s'
        executor.spin_once(timeout_sec=0.05)


def _publish(mirrors: LocalizationPublisher, x: float) -> None:
    """A dead reckoning at (x, 1, 0.5), the map 0.25 m further in x: the pose at (x + 0.25, 1, 0.5)."""
    mirrors.publish(stamp=x, dead_reckoning=np.array([x, 1.0, 0.5]), dr_cov=np.eye(3) * 0.01, tv=0.3, rv=0.1,
                    adjustment=np.array([0.25, 0.0, 0.0]), pose=np.array([x + 0.25, 1.0, 0.5]),
                    pose_cov=np.eye(3) * 0.04)


def test_odom_pose_and_tf_are_sent_only_to_a_reader(ros_domain: int, rclpy_context: Any) -> None:
    node = rclpy.create_node('mirrors_check', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    try:
        mirrors = LocalizationPublisher(node)
        for x in (1.0, 2.0, 3.0):                          # nobody listens: nothing is built
            _publish(mirrors, x)
        assert mirrors._odom.header.stamp.sec == 0 and mirrors._pose.header.stamp.sec == 0
        assert mirrors._tf.transforms[1].header.stamp.sec == 0
        odometry: list[Odometry] = []
        poses: list[PoseWithCovarianceStamped] = []
        transforms: list[TFMessage] = []
        node.create_subscription(Odometry, 'odom', odometry.append, 10)
        _until(executor, lambda: watched(mirrors.odom), 'match of the odom reader')
        _publish(mirrors, 4.0)
        _until(executor, lambda: bool(odometry), 'odometry after the match')
        assert mirrors._pose.header.stamp.sec == 0       # pose and tf still have no reader
        node.create_subscription(PoseWithCovarianceStamped, 'pose', poses.append, 10)
        node.create_subscription(TFMessage, 'tf', transforms.append, 10)
        _until(executor, lambda: watched(mirrors.pose) and watched(mirrors.tf), 'match of the pose and tf readers')
        _publish(mirrors, 5.0)
        _until(executor, lambda: len(odometry) == 2 and poses and transforms, 'the three after the matches')
        assert odometry[0].header.stamp.sec == 4 and odometry[1].pose.pose.position.x == 5.0
        assert odometry[1].twist.twist.linear.x == 0.3
        pose = poses[0].pose
        assert (pose.pose.position.x, pose.pose.position.y) == (5.25, 1.0)
        assert 2 * math.atan2(pose.pose.orientation.z, pose.pose.orientation.w) == pytest.approx(0.5, abs=1e-12)
        assert pose.covariance[0] == 0.04 and pose.covariance[14] == UNKNOWN_VARIANCE
        to_odom, to_base = transforms[0].transforms
        assert (to_odom.header.frame_id, to_odom.child_frame_id) == ('map', 'odom')
        assert to_odom.transform.translation.x == 0.25 and to_base.transform.translation.x == 5.0
    finally:
        executor.shutdown()
        node.destroy_node()
