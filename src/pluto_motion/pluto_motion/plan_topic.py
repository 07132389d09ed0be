"""The motionModule's plan as ``nav_msgs/Path`` on ``plan`` (``/plan`` in the root namespace), for
RViz and Foxglove: the path a planned moveto follows, from where the robot was when it planned to
the goal, in frame ``map`` (REP-105), sent on every plan and replan.  Transient local, depth 1: a
viewer that comes later gets the plan being followed (or the last one), as with ``/map``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

__all__ = ['PLAN_TOPIC', 'PlanPublisher', 'plan_path']

PLAN_TOPIC = 'plan'


def plan_path(points: Sequence[Sequence[float]], stamp: Any) -> Path:
    """The path through ``points`` (x, y in the map frame), stamped ``stamp`` (builtin Time)."""
    path = Path()
    path.header.frame_id = 'map'
    path.header.stamp = stamp
    for x, y in points:
        pose = PoseStamped()
        pose.header = path.header
        pose.pose.position.x, pose.pose.position.y = float(x), float(y)
        pose.pose.orientation.w = 1.0
        path.poses.append(pose)
    return path


class PlanPublisher:
    """Publishes a behaviour's plan each time it changes (a new plan is a new list of points)."""

    def __init__(self, node: Any) -> None:
        qos = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.publisher = node.create_publisher(Path, PLAN_TOPIC, qos)
        self._shown: object = None
        self.published = 0

    def update(self, behaviour: Any, stamp: Any) -> None:
        """After the behaviour's step: its follower's points (start, then the waypoints), if it
        follows a plan it has not yet published."""
        follower = getattr(behaviour, 'follower', None)
        points = getattr(follower, 'points', None)
        if not points or points is self._shown:
            return
        self._shown = points
        self.publisher.publish(plan_path(points, stamp))
        self.published += 1
