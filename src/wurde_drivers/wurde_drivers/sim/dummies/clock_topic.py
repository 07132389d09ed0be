"""The simulator's time on ``/clock`` (rosgraph_msgs/Clock), for nodes with ``use_sim_time``.

The dummy base owns the simulated world's time (:class:`wurde_drivers.sim.clock.SimClock`) and
publishes it every step, so that any node started with ``--ros-args -p use_sim_time:=true`` —
every WURDE module's auto-timestamps (``CommsManager.now``), RViz, a bag recorder — stamps with the
simulator's time at any time scale.  ``/clock`` is one topic per domain (rclpy's TimeSource
listens on the absolute name): run one simulator per domain when nodes use simulated time.
"""

from __future__ import annotations

from typing import Any

from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock
from wurde_core import Time

from ...ros_std import watched

CLOCK_TOPIC = '/clock'


class ClockPublisher:
    """Publishes simulated time stamps on ``/clock``."""

    def __init__(self, node: Any) -> None:
        # reliable: matches rclpy's best-effort TimeSource subscription and reliable recorders
        self.publisher = node.create_publisher(Clock, CLOCK_TOPIC,
                                               QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE))
        self._message = Clock()

    def publish(self, stamp: float) -> None:
        """The stamp, while anyone listens (a node with use_sim_time, a recorder)."""
        if not watched(self.publisher):
            return
        Time(stamp).to_msg(self._message.clock)
        self.publisher.publish(self._message)
