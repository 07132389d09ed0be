"""The simulator's people as the truth, on ``/<base>/ground_truth/people`` (visualization_msgs/MarkerArray).

The dummy base publishes where every person of the sim config is (:mod:`wurde_drivers.sim.people`)
at its odometry rate, stamped with the simulated time, beside the robot's own truth
(``/<base>/ground_truth/odom``): a topic of their own under ``ground_truth/``, frame ``map``, so
that nobody takes it for a people detector's output.  A MarkerArray is what RViz and Foxglove
draw as they are, and it says everything a check needs to measure the robot's clearance from the
people, one marker per person, every message holding all of them:

========================== ======================================================================
field                      what
========================== ======================================================================
``ns``, ``id``             ``people``, the person's index in the config
``text``                   the person's name (drawn only by text markers; there for checks)
``type``                   ``CYLINDER`` (a disc person) or ``CUBE`` (a box)
``pose``                   the body's centre: ``x``, ``y`` on the map, ``z`` half its height; the
                           orientation its heading (a box's length lies along it)
``scale``                  a disc's diameter twice and its height; a box's length, width, height
========================== ======================================================================

``record`` takes the topic like any other, so every run's MCAP holds the people's truth.
"""

from __future__ import annotations

import math
from typing import Any

from rclpy.qos import QoSProfile, ReliabilityPolicy
from visualization_msgs.msg import Marker, MarkerArray
from wurde_core.ros_messages import set_stamp

from ...ros_std import std_topic, watched
from ..people import People

__all__ = ['NAMESPACE', 'PeoplePublisher', 'people_topic']

#: The markers' namespace.
NAMESPACE = 'people'
#: RGBA of a person as drawn: an orange that stands out from maps and scans.
_COLOUR = (1.0, 0.55, 0.1, 0.9)


def people_topic(base: str) -> str:
    """The topic of ``base``'s people, relative as every standard topic (``/<base>/ground_truth/people``)."""
    return std_topic(base, 'ground_truth/people')


class PeoplePublisher:
    """Publishes the people of a world at a stamp, one MarkerArray per call."""

    def __init__(self, node: Any, base: str, people: People) -> None:
        self.publisher = node.create_publisher(MarkerArray, people_topic(base),
                                               QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
        self.people = people

    def publish(self, stamp: float) -> None:
        """Everyone where they are at ``stamp`` (s, simulated time); nothing while unwatched."""
        if not watched(self.publisher):
            return
        message = MarkerArray()
        for index, (person, (x, y, heading)) in enumerate(zip(self.people, self.people.poses_at(stamp))):
            body = person.body
            marker = Marker()
            set_stamp(marker, stamp)
            marker.header.frame_id = 'map'
            marker.ns = NAMESPACE
            marker.id = index
            marker.text = person.name
            marker.type = Marker.CUBE if body.is_box else Marker.CYLINDER
            marker.action = Marker.ADD
            marker.pose.position.x = float(x)
            marker.pose.position.y = float(y)
            marker.pose.position.z = body.height / 2
            marker.pose.orientation.z = math.sin(heading / 2)
            marker.pose.orientation.w = math.cos(heading / 2)
            marker.scale.x = body.length if body.is_box else 2 * body.radius
            marker.scale.y = body.width if body.is_box else 2 * body.radius
            marker.scale.z = body.height
            marker.color.r, marker.color.g, marker.color.b, marker.color.a = _COLOUR
            message.markers.append(marker)
        self.publisher.publish(message)
