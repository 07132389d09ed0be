"""Pluto's localization: localModule with its five pose streams, poseModule, slamModule and the
loc proxy.

The estimation core (pure numpy, no ROS) is exported here: line features from a laser scan, the
wall map, data association, the pose Kalman filter, the odometry noise model and Pluto 7.1's
find-wall; and the slamModule's line SLAM on a compressed EKF.
"""

from .find_wall import FoundWall, find_wall
from .lines import LineFeature, extract_lines
from .matching import Match, MatchSettings, Matching, match_lines
from .odometry_model import OdometryNoiseModel, increment_covariance, laser_increment
from .pose_filter import PoseFilter, UpdateResult
from .slam_filter import LINE_EXTRACTION, SlamFilter, SlamSettings, SlamUpdate
from .wall_map import WallMap

__all__ = [
    'LINE_EXTRACTION', 'FoundWall', 'LineFeature', 'Match', 'MatchSettings', 'Matching',
    'OdometryNoiseModel', 'PoseFilter', 'SlamFilter', 'SlamSettings', 'SlamUpdate', 'UpdateResult',
    'WallMap', 'extract_lines', 'find_wall', 'increment_covariance', 'laser_increment', 'match_lines',
]
