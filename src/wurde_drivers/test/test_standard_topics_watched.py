"""The standard mirrors are built only while someone subscribes (issue 39; what that saves is
measured, not tested), and lose nothing by it: real rclpy, one process.  A subscriber that comes
late is matched (``watched``) and gets what is published from then on, and the odometry
covariance, which grows with the path, is the whole path's although nobody read the odometry
before."""

from __future__ import annotations

import time
from typing import Any

import rclpy
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor

from wurde_drivers.ros_std import OdometryPublisher, watched
from wurde_drivers.ros_std_covariance import OdometryCovariance

NOISE = {'trans': 0.05, 'rot': 0.02, 'drift': 0.01}


def _until(executor: SingleThreadedExecutor, predicate: Any, what: str, timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, f'no {what} within {timeout} s'
        executor.spin_once(timeout_sec=0.05)


def test_odometry_is_sent_only_when_watched_and_its_covariance_covers_the_whole_path(
        ros_domain: int, rclpy_context: Any) -> None:
    node = rclpy.create_node('watched_check', context=rclpy_context)
    executor = SingleThreadedExecutor(context=rclpy_context)
    executor.add_node(node)
    try:
        odometry = OdometryPublisher(node, 'PlutoBase', covariance=OdometryCovariance(**NOISE))
        reference = OdometryCovariance(**NOISE)
        path = [(0.1 * k, 0.02 * k, 0.01 * k, 0.1 * k) for k in range(50)]
        assert not watched(odometry.publisher)
        for x, y, theta, stamp in path:                   # nobody listens
            odometry.publish(x, y, theta, 1.0, 0.1, stamp)
            reference.update(x, y, theta, stamp)
        got: list[Odometry] = []
        node.create_subscription(Odometry, 'PlutoBase/odom', got.append, 10)
        _until(executor, lambda: watched(odometry.publisher), 'match of the subscriber')
        odometry.publish(5.0, 1.0, 0.5, 1.0, 0.1, 5.0)
        reference.update(5.0, 1.0, 0.5, 5.0)
        _until(executor, lambda: bool(got), 'odometry after the match')
        assert got[0].pose.pose.position.x == 5.0
        expected = reference.pose6()
        assert expected[0] > 0.0
        assert max(abs(a - b) for a, b in zip(got[0].pose.covariance, expected)) <= 1e-12
    finally:
        executor.shutdown()
        node.destroy_node()
