"""Reading a standard topic as a late subscriber would (``ros2 topic echo --once`` with the
publisher's durability): a node in a context of its own, its own executor, a deadline."""

from __future__ import annotations

import time
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

__all__ = ['latched']


def latched(topic: str, message_type: type, timeout: float = 30.0) -> Any:
    """The message a transient-local subscriber to ``topic`` gets first (the publisher's last,
    kept for late readers).

    :param topic: the topic's full name.
    :param message_type: its message class.
    :param timeout: fail the test (AssertionError) after this many seconds.
    """
    context = Context()
    rclpy.init(context=context)
    try:
        node = rclpy.create_node('latched_reader', context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        got: list[Any] = []
        qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        node.create_subscription(message_type, topic, got.append, qos)
        deadline = time.monotonic() + timeout
        while not got:
            assert time.monotonic() < deadline, f'{topic}: nothing within {timeout} s'
            executor.spin_once(timeout_sec=0.1)
        return got[0]
    finally:
        rclpy.shutdown(context=context)
