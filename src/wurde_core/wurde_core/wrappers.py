"""The guide's special wrappers: verbs over a transport interface (guide 1.1.5, 7.3, 7.7).

``ObstacleAvoider`` wraps ObstacleAvoiderTransport and ``VectorMover`` wraps VectorMoverTransport:
a consumer calls a verb, which sets the request members and sends the request.  ``Navigator``
wraps NavigatorTransport with CARMEN's navigator verbs (Programming with CARMEN 4.2.1, 4.3).  ``info.brake``
tells whether the supplier holds the robot; ``requests.brake.set_value(False)`` releases it, as in
the guide's BlindTeleop example.
"""

from __future__ import annotations

import math

from .geometry import PlanarPoint, PVector
from .robot_object import RobotObject

#: ObstacleAvoiderTransport ``mode`` values (see its interface description).
MODE_STOP, MODE_POINT, MODE_ANGLE = 0, 1, 2


class ObstacleAvoider(RobotObject, interface='ObstacleAvoiderTransport'):
    """Move around obstacles: ``stop()``, ``move_to_relative_point(p)``, ``rotate_to_relative_angle(a)``."""

    def stop(self) -> bool:
        """Stop the robot (and keep it stopped)."""
        self.requests.mode.set_value(MODE_STOP)
        return self.publish_request()

    def move_to_relative_point(self, goal: PlanarPoint) -> bool:
        """Drive to ``goal``, avoiding obstacles.

        :param goal: the point in m, robot frame (x forward, y left).
        :returns: whether the request was sent (False outside Run or before the stream is
            connected).
        """
        self.requests.mode.set_value(MODE_POINT)
        self.requests.goal.set_value(goal)
        return self.publish_request()

    def rotate_to_relative_angle(self, angle: float) -> bool:
        """Turn in place by ``angle``.

        :param angle: rad, counter-clockwise positive.
        :returns: whether the request was sent (False outside Run or before the stream is
            connected).
        """
        self.requests.mode.set_value(MODE_ANGLE)
        self.requests.angle.set_value(float(angle))
        return self.publish_request()

    def set_brake(self, on: bool) -> bool:
        """Set or release the brake.

        :param on: True holds the robot; False releases it.
        :returns: whether the request was sent (False outside Run or before the stream is
            connected).
        """
        self.requests.brake.set_value(bool(on))
        return self.publish_request()


class VectorMover(RobotObject, interface='VectorMoverTransport'):
    """Drive along a vector relative to the robot: ``move(vector)``, ``stop()``."""

    def move(self, vector: PVector) -> bool:
        """Drive along ``vector``, brake released.

        :param vector: ``magnitude()`` metres in direction ``angle()`` (rad, robot frame,
            counter-clockwise from forward).
        :returns: whether the request was sent (False outside Run or before the stream is
            connected).
        """
        self.requests.vector.set_value(vector)
        self.requests.brake.set_value(False)
        return self.publish_request()

    def move_to(self, x: float, y: float) -> bool:
        """Drive to the point (x, y) relative to the robot (:meth:`move` of its polar vector).

        :param x: m forward.
        :param y: m to the left.
        :returns: whether the request was sent (False outside Run or before the stream is
            connected).
        """
        return self.move(PVector(math.hypot(x, y), math.atan2(y, x)))

    def stop(self) -> bool:
        """Stop: a zero vector with the brake on."""
        self.requests.vector.set_value(PVector(0.0, 0.0))
        self.requests.brake.set_value(True)
        return self.publish_request()


#: NavigatorTransport ``stop_reason`` values: CARMEN's autonomous-stopped reasons, and 3 for a goal
#: that could not be reached (its reason is in the navigator's log).
STOP_NONE, GOAL_REACHED, USER_STOPPED, STOP_FAILED = 0, 1, 2, 3


class Navigator(RobotObject, interface='NavigatorTransport'):
    """A map-based navigator: ``set_goal(x, y)``, ``set_goal_place(name)``, ``go()``, ``stop()``; its
    data is the status (robot pose, goal, ``autonomous``, ``stop_reason``)."""

    def set_goal(self, x: float, y: float) -> bool:
        """Set the one goal (carmen_navigator_set_goal); :meth:`go` starts the motion.

        :param x: m, map frame.
        :param y: m, map frame.
        :returns: whether the request was sent (False outside Run or before the stream is
            connected).
        """
        self.requests.goal.set_value(PlanarPoint(float(x), float(y)))
        return self.publish_request()

    def set_goal_place(self, name: str) -> bool:
        """Set the goal at a place of the map (carmen_navigator_set_goal_place).

        :param name: the place's name in the map; no effect if the map has none.
        :returns: whether the request was sent (False outside Run or before the stream is
            connected).
        """
        self.requests.goal_place.set_value(str(name))
        return self.publish_request()

    def go(self) -> bool:
        """Autonomous motion to the goal (carmen_navigator_go)."""
        self.requests.autonomous.set_value(True)
        return self.publish_request()

    def stop(self) -> bool:
        """Leave autonomous motion (carmen_navigator_stop)."""
        self.requests.autonomous.set_value(False)
        return self.publish_request()
