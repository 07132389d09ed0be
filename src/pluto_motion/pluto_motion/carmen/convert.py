"""Our WURDE streams' events as CARMEN's messages: each function fills a message in place.

``d`` is an event's data view (``obj.data``), ``info`` its stream's info (``obj.info``).  Units
are already CARMEN's (metres, radians, seconds), so the work is naming, ordering and the few
values CARMEN computes itself: a sonar ring's offsets, a scan's laser pose (CARMEN's robot
module interpolates the odometry at the scan's time), the localized pose's deviations.
"""

from __future__ import annotations

import math
from typing import Any

from pluto_nav.geometry import compose
from pluto_nav.pose_history import PoseHistory
from pluto_nav.streams import NOBODY, read_pose

from ..sonar_guard import ring_layout
from .messages import (CARMEN_NAVIGATOR_GOAL_REACHED_v, CARMEN_NAVIGATOR_UNKNOWN_v,
                       CARMEN_NAVIGATOR_USER_STOPPED_v, carmen_point_t, carmen_traj_point_t)

#: NavigatorTransport ``stop_reason`` (1 goal reached, 2 user stopped, 3 failed) as CARMEN's reason.
REASONS = {1: CARMEN_NAVIGATOR_GOAL_REACHED_v, 2: CARMEN_NAVIGATOR_USER_STOPPED_v,
           3: CARMEN_NAVIGATOR_UNKNOWN_v}


def stamp_and_host(msg: Any, d: Any) -> None:
    """CARMEN's timestamp (acquisition time, s) and host (the origin: the supplying module).

    :param msg: the CARMEN message filled.
    :param d: the event's data view.
    """
    msg.timestamp = d.timestamp.get_seconds()
    msg.host = d.source


def odometry(msg: Any, d: Any) -> None:
    """Egomotion (``<base>Motion``) → carmen_base_odometry_message.

    :param msg: the carmen_base_odometry_message filled.
    :param d: the Egomotion data view.
    """
    loc = d.location
    msg.x, msg.y, msg.theta = float(loc.x()), float(loc.y()), float(loc.theta())
    msg.tv, msg.rv, msg.acceleration = float(d.tv), float(d.rv), float(d.acceleration)
    stamp_and_host(msg, d)


def sensor_offsets(info: Any, count: int) -> list[carmen_point_t]:
    """Each sensor's pose on the robot from a RangeFinder's info: its positions, or its uniform
    ring (the first at the offsets, each next turned by theta_separation about the centre).

    :param info: the RangeFinder's info view.
    :param count: the number of sensors, for a uniform ring.
    """
    positions = list(info.sensor_positions.get_value())
    if positions:
        return [carmen_point_t(float(p.x()), float(p.y()), float(p.theta())) for p in positions]
    layout = ring_layout(count, float(info.theta_offset.get_value()), float(info.theta_separation.get_value()),
                         float(info.x_offset.get_value()), float(info.y_offset.get_value()))
    return [carmen_point_t(x, y, theta) for x, y, theta in layout]


def ranges(msg: Any, d: Any, count_field: str) -> None:
    """A RangeFinder's readings (m) as ``range`` and its count as ``count_field``.

    :param msg: the CARMEN message filled.
    :param d: the RangeFinder data view.
    :param count_field: the message's count field (``num_sonars``, ``num_readings``).
    """
    msg.range = [float(r) for r in d.ranges]
    setattr(msg, count_field, len(msg.range))
    stamp_and_host(msg, d)


def sonar(msg: Any, d: Any, info: Any) -> None:
    """RangeFinder (``<base>Sonar``) → carmen_base_sonar_message.

    :param msg: the carmen_base_sonar_message filled.
    :param d: the RangeFinder data view.
    :param info: the stream's info view, for the sonar offsets.
    """
    ranges(msg, d, 'num_sonars')
    msg.sonar_offsets = sensor_offsets(info, msg.num_sonars)


def bumper(msg: Any, d: Any) -> None:
    """Bumper (``<base>Bumpers``) → carmen_base_bumper_message: 1.0 pressed, 0.0 free.

    :param msg: the carmen_base_bumper_message filled.
    :param d: the Bumper data view.
    """
    msg.range = [1.0 if pressed else 0.0 for pressed in d.bumpers]
    msg.num_sonars = len(msg.range)
    stamp_and_host(msg, d)


def laser_mount(info: Any, count: int) -> tuple[float, float, float]:
    """The laser's pose on the robot (x, y, yaw of its middle beam) from its RangeFinder info.

    :param info: the RangeFinder's info view.
    :param count: the number of beams, for a uniform fan.
    """
    positions = list(info.sensor_positions.get_value())
    if positions:
        middle = positions[len(positions) // 2]
        return float(middle.x()), float(middle.y()), float(middle.theta())
    yaw = float(info.theta_offset.get_value()) + float(info.theta_separation.get_value()) * (count - 1) / 2
    return float(info.x_offset.get_value()), float(info.y_offset.get_value()), yaw


def robot_laser(msg: Any, d: Any, info: Any, odometry_at: PoseHistory, velocity: tuple[float, float]) -> bool:
    """A scan and the odometry at its time → carmen_robot_laser_message.  False (message
    untouched) when the odometry does not cover the scan's time yet.

    :param msg: the carmen_robot_laser_message filled.
    :param d: the RangeFinder data view.
    :param info: the stream's info view, for the laser's mount.
    :param odometry_at: the base's odometry poses by time.
    :param velocity: the base's newest (tv, rv), m/s and rad/s.
    """
    stamp = d.timestamp.get_seconds()
    robot = odometry_at.at(stamp)
    if robot is None:
        return False
    ranges(msg, d, 'num_readings')
    laser = compose(robot, laser_mount(info, msg.num_readings))
    msg.x, msg.y, msg.theta = float(laser[0]), float(laser[1]), float(laser[2])
    msg.odom_x, msg.odom_y, msg.odom_theta = robot
    msg.tv, msg.rv = velocity
    return True


def globalpos(msg: Any, d: Any, odometry_at: PoseHistory) -> None:
    """LocalizationPose (``Localization/Pose``) → carmen_localize_globalpos_message.  Converged
    while an estimator (poseModule, slamModule) holds the pose; odometrypos is the base's
    odometry at the pose's stamp, or the pose's own when the odometry does not cover it.

    :param msg: the carmen_localize_globalpos_message filled.
    :param d: the LocalizationPose data view.
    :param odometry_at: the base's odometry poses by time.
    """
    pose = read_pose(d)
    x, y, theta = pose.xytheta
    cov = pose.covariance
    msg.globalpos = carmen_point_t(x, y, theta)
    msg.globalpos_std = carmen_point_t(*(math.sqrt(max(float(cov[i, i]), 0.0)) for i in range(3)))
    msg.globalpos_xy_cov = float(cov[0, 1])
    odom = odometry_at.at(pose.stamp)
    msg.odometrypos = carmen_point_t(*(odom if odom is not None else (x, y, theta)))
    msg.converged = int(pose.setter > NOBODY)
    stamp_and_host(msg, d)


def navigator_status(msg: Any, d: Any, velocity: tuple[float, float]) -> None:
    """NavigatorTransport data → carmen_navigator_status_message (the robot's velocities are the
    base's newest odometry).

    :param msg: the carmen_navigator_status_message filled.
    :param d: the NavigatorTransport data view.
    :param velocity: the base's newest (tv, rv), m/s and rad/s.
    """
    robot = d.robot
    msg.autonomous, msg.goal_set = int(bool(d.autonomous)), int(bool(d.goal_set))
    msg.goal = carmen_point_t(float(d.goal.x()), float(d.goal.y()), 0.0)
    msg.robot = carmen_traj_point_t(float(robot.x()), float(robot.y()), float(robot.theta()), *velocity)
    stamp_and_host(msg, d)


def navigator_plan(msg: Any, d: Any) -> None:
    """NavigatorTransport data → carmen_navigator_plan_message.

    :param msg: the carmen_navigator_plan_message filled.
    :param d: the NavigatorTransport data view.
    """
    msg.path = [carmen_traj_point_t(float(p.x()), float(p.y())) for p in d.plan]
    msg.path_length = len(msg.path)
    stamp_and_host(msg, d)


def navigator_map(msg: Any, info: Any) -> None:
    """MapServer info (row-major, x fastest) → carmen_navigator_map_message (CARMEN's x-major).

    :param msg: the carmen_navigator_map_message filled.
    :param info: the MapServer's info view.
    """
    width, height = int(info.width.get_value()), int(info.height.get_value())
    cells = list(info.cells.get_value())
    msg.data = [float(cells[y * width + x]) for x in range(width) for y in range(height)]
    msg.size = len(msg.data)
    msg.config.x_size, msg.config.y_size = width, height
    msg.config.resolution = float(info.resolution.get_value())
    msg.config.map_name = str(info.map_name.get_value())
    msg.timestamp = info.timestamp.get_seconds()
    msg.host = info.source
