"""The avoidModule's wall follow (Pluto 6.2: "The wall follow command is designed to hold a camera,
extended from the back and to the left of the robot, at a safe but constant distance from the
'wall'.  The robot will move along the wall in this posture.").

Our reading: the wall is on the robot's left; the laser's left side sees it (beams from
:data:`LEFT_FROM` to :data:`LEFT_TO` rad, points within :data:`WALL_REACH` m).  A straight line is
fitted to those points (total least squares); the controller turns so that the robot runs parallel
to it with the camera (:data:`CAMERA`, back-left of the robot centre) at the distance asked for:

    approach = clamp(DISTANCE_GAIN * (camera_distance - distance), MAX_APPROACH)
    rv = clamp(ANGLE_GAIN * (wall_angle + approach), MAX_RV)

``wall_angle`` is the wall's direction relative to the robot's heading (positive: the wall bends
away to the left); ``approach`` the angle (towards the wall when too far) the robot should hold
relative to it.  The speed is ``cos(wall_angle)`` of the speed asked for, at least ``SLOW_SHARE``.  A wall ahead nearer than :data:`CORNER_M` (free distance of the footprint) is an
inside corner: the robot turns right in place.  No wall seen: straight on, slowly turning left to
find one (``SEARCH_RV``).  Velocities go to the drive in velocity mode.
"""

from __future__ import annotations

import math

import numpy as np

from .laser_guard import free_distance

__all__ = ['ANGLE_GAIN', 'CAMERA', 'CORNER_M', 'DEFAULT_DISTANCE', 'DISTANCE_GAIN', 'LEFT_FROM', 'LEFT_TO',
           'MAX_APPROACH', 'MAX_RV', 'SEARCH_RV', 'SLOW_SHARE', 'WALL_REACH', 'fit_left_wall', 'wall_follow_step']

#: The camera's mount (m, robot frame: x forward, y left): behind the centre and to the left.
CAMERA = (-0.45, 0.30)
#: The camera-to-wall distance kept when the command gives none (m).
DEFAULT_DISTANCE = 0.8
#: Bearings (rad, robot frame) of the laser points taken as the left wall, and their reach (m).
LEFT_FROM, LEFT_TO, WALL_REACH = math.radians(30.0), math.radians(100.0), 3.0
#: Controller: rad/s per rad of angle error, rad of approach per m of distance error, the largest
#: approach angle (rad), the angular velocity limit (rad/s), the least share of the speed.
ANGLE_GAIN, DISTANCE_GAIN, MAX_APPROACH, MAX_RV, SLOW_SHARE = 1.0, 1.0, 0.5, 0.6, 0.3
#: An obstacle ahead nearer than this (free distance, m) is a corner: turn right in place.
CORNER_M = 0.6
#: Turn rate (rad/s) while no wall is seen.
SEARCH_RV = 0.15
_MIN_POINTS = 5


def fit_left_wall(points: np.ndarray) -> tuple[float, float] | None:
    """The wall on the left as (angle, camera distance): the fitted line's direction relative to the
    robot's heading (rad, in (-pi/2, pi/2]) and the camera's distance to it (m); None when fewer than
    a handful of points lie there."""
    if len(points) == 0:
        return None
    bearing = np.arctan2(points[:, 1], points[:, 0])
    d = np.hypot(points[:, 0], points[:, 1])
    left = points[(bearing >= LEFT_FROM) & (bearing <= LEFT_TO) & (d < WALL_REACH)]
    if len(left) < _MIN_POINTS:
        return None
    centre = left.mean(axis=0)
    _, _, vt = np.linalg.svd(left - centre)
    direction = vt[0]
    if direction[0] < 0:
        direction = -direction
    normal = np.array([-direction[1], direction[0]])
    angle = math.atan2(direction[1], direction[0])
    distance = abs(float((centre - np.asarray(CAMERA)) @ normal))
    return angle, distance


def wall_follow_step(points: np.ndarray, speed: float, distance: float = 0.0, *,
                     radius: float = 0.35) -> tuple[float, float]:
    """(tv, rv) to follow the wall on the left at ``distance`` (0: :data:`DEFAULT_DISTANCE`) from the
    camera, given the laser ``points`` ((N, 2), robot frame)."""
    distance = distance or DEFAULT_DISTANCE
    if free_distance(points, radius, 0.05) < CORNER_M:
        return 0.0, -MAX_RV
    wall = fit_left_wall(points)
    if wall is None:
        return speed, SEARCH_RV
    angle, camera_distance = wall
    approach = max(-MAX_APPROACH, min(MAX_APPROACH, DISTANCE_GAIN * (camera_distance - distance)))
    rv = max(-MAX_RV, min(MAX_RV, ANGLE_GAIN * (angle + approach)))
    return speed * max(SLOW_SHARE, math.cos(angle)), rv
