"""Standard ROS 2 messages published alongside the WURDE streams (docs/design.md, "Topics and QoS").

ROS tools (RViz, Nav2, ``ros2 topic echo``) expect standard messages, so the device modules give
them next to their WURDE streams: for a device module ``N``, ``/N/scan``, ``/N/odom``,
``/N/cmd_vel`` (in), ``/N/imu``, ``/N/fix``, ``/N/ground_truth/...``, ``/N/sonar``,
``/N/bumpers``, ``/N/battery``, ``/N/joint_states`` and ``/tf_static``.  The table of standard
topics of docs/simulator.md ("The simulated robot and the drivers") says what each carries, in which frame
and with which covariance.  This module holds the scan, odometry, ground truth, cmd_vel, IMU and
fix; :mod:`~wurde_drivers.ros_std_base`, :mod:`~wurde_drivers.ros_std_joints` and
:mod:`~wurde_drivers.ros_std_frames` the others.

Only plain stream names get these topics (``N`` is the stream's topic path, see
:func:`wurde_core.naming.stream_segment_path`); every name comes from :func:`std_topic`. Frames
follow one rule (:func:`wurde_drivers.ros_std_frames.frame_of`); covariances and their sources are
in :mod:`wurde_drivers.ros_std_covariance`.  A mirror is built and sent only while something
subscribes to it (:func:`watched`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import Imu, LaserScan, NavSatFix, NavSatStatus
from wurde_core.naming import stream_segment_path
from wurde_core.ros_adaptor import polled, take, watched
from wurde_core.ros_messages import quaternion, set_stamp

from .ros_std_covariance import ImuCovariance, ImuNoise, OdometryCovariance, fix_covariance
from .ros_std_frames import frame_of

__all__ = ['watched', 'FixPublisher', 'ImuPublisher', 'OdometryPublisher', 'ScanPublisher', 'TwistInbox',
           'ground_truth_publisher', 'std_topic']

_QOS = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)


def std_topic(stream: str, leaf: str) -> str:
    """The standard topic ``leaf`` of ``stream``: ``S/<leaf>``, relative, so ``/S/<leaf>`` for a
    module started plainly and ``/robot1/S/<leaf>`` in namespace ``/robot1``.  Every name here
    comes from this."""
    return f'{stream_segment_path(stream)}/{leaf}'


class ScanPublisher:
    """``/S/scan``: the scan in robot order, counter-clockwise (REP-103): from −90° to +90° (the
    SICK's fan, whatever the beam count), or from ``angle_min`` by ``angle_increment``."""

    def __init__(self, node: Any, stream: str, *, max_range: float, time_increment: float = 0.0,
                 frame: str | None = None, angle_min: float | None = None,
                 angle_increment: float | None = None) -> None:
        """``time_increment``: seconds between two measurements (the device's fact, 0 if unknown)."""
        self.publisher = node.create_publisher(LaserScan, std_topic(stream, 'scan'), _QOS)
        self.frame = frame or frame_of(stream)
        self.max_range = max_range
        self.time_increment = time_increment
        self.angle_min, self.angle_increment = angle_min, angle_increment

    def publish(self, ranges: Sequence[float], stamp: float, scan_time: float) -> None:
        if not watched(self.publisher):
            return
        msg = LaserScan()
        set_stamp(msg, stamp)
        msg.header.frame_id = self.frame
        count = len(ranges)
        if self.angle_increment is None or self.angle_min is None:
            msg.angle_min = -math.pi / 2
            msg.angle_max = math.pi / 2
            msg.angle_increment = math.pi / (count - 1) if count > 1 else 0.0
        else:
            msg.angle_min = self.angle_min
            msg.angle_max = self.angle_min + self.angle_increment * max(count - 1, 0)
            msg.angle_increment = self.angle_increment
        msg.scan_time = scan_time
        msg.time_increment = self.time_increment if count else 0.0
        msg.range_min = 0.0
        msg.range_max = self.max_range
        msg.ranges = [float(r) for r in ranges]
        self.publisher.publish(msg)


class OdometryPublisher:
    """``/S/odom``: pose and twist of ``base_link`` in ``odom`` (REP-105).

    :param covariance: grows the pose and twist covariances from the base's noise figures; None
        publishes zeros (only for the simulator's ground truth, which is exact).
    :param leaf: the topic's leaf; ``frame`` the pose's frame.
    """

    def __init__(self, node: Any, stream: str, *, covariance: OdometryCovariance | None,
                 leaf: str = 'odom', frame: str = 'odom') -> None:
        self.publisher = node.create_publisher(Odometry, std_topic(stream, leaf), _QOS)
        self.covariance = covariance
        self.frame = frame

    def publish(self, x: float, y: float, theta: float, tv: float, rv: float, stamp: float) -> None:
        if self.covariance is not None:
            self.covariance.update(x, y, theta, stamp)       # grows whether or not anyone reads it
        if not watched(self.publisher):
            return
        msg = Odometry()
        set_stamp(msg, stamp)
        msg.header.frame_id = self.frame
        msg.child_frame_id = 'base_link'
        if self.covariance is not None:
            msg.pose.covariance = self.covariance.pose6()
            msg.twist.covariance = self.covariance.twist6()
        msg.pose.pose.position.x = x
        msg.pose.pose.position.y = y
        msg.pose.pose.orientation.z = math.sin(theta / 2)
        msg.pose.pose.orientation.w = math.cos(theta / 2)
        msg.twist.twist.linear.x = tv
        msg.twist.twist.angular.z = rv
        self.publisher.publish(msg)


def ground_truth_publisher(node: Any, base: str) -> OdometryPublisher:
    """``/<base>/ground_truth/odom``: the simulator's true pose of ``base_link`` in ``map``.

    A topic of its own, and frame ``map``, so that nobody takes it for odometry; its covariance
    is zero because it is exact (the one standard message here that says so).
    """
    return OdometryPublisher(node, base, covariance=None, leaf='ground_truth/odom', frame='map')


class TwistInbox:
    """``/S/cmd_vel``: the newest Twist, taken without an executor as the WURDE channels are."""

    def __init__(self, node: Any, stream: str) -> None:
        self.subscription = node.create_subscription(Twist, std_topic(stream, 'cmd_vel'),
                                                     polled, _QOS)

    def take(self) -> Twist | None:
        """The newest Twist that arrived since the last call, or None."""
        newest = None
        for newest in take(self.subscription):
            pass
        return newest


class ImuPublisher:
    """``/S/imu``: orientation, angular velocity and linear acceleration (REP-103, z up).

    :param noise: the raw sample's noise figures (the module names their source).
    :param tau: the DMU filter's time constant (s): it lowers the rates' and accelerations'
        variance.
    """

    def __init__(self, node: Any, stream: str, *, noise: ImuNoise, tau: float) -> None:
        self.publisher = node.create_publisher(Imu, std_topic(stream, 'imu'), _QOS)
        self.frame = frame_of(stream)
        self.covariance = ImuCovariance(noise, tau)

    def publish(self, state: Any, stamp: float) -> None:
        cov = self.covariance
        cov.update(stamp)                                   # kept whether or not anyone reads it
        if not watched(self.publisher):
            return
        msg = Imu()
        set_stamp(msg, stamp)
        msg.header.frame_id = self.frame
        msg.orientation_covariance = cov.orientation()
        msg.angular_velocity_covariance = cov.angular_velocity()
        msg.linear_acceleration_covariance = cov.linear_acceleration()
        q = quaternion(state.theta, state.phi or 0.0, state.psi or 0.0)
        msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = q
        msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z = (
            state.rate_x, state.rate_y, state.rate_z)
        msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z = (
            state.accel_x, state.accel_y, state.accel_z)
        self.publisher.publish(msg)


#: NMEA GGA fix quality → NavSatStatus (0 invalid, 1 GPS, 2 DGPS, 3 PPS, 4/5 RTK).  6 (dead
#: reckoning), 7 (manual input) and 8 (simulation) are no satellite fix: STATUS_NO_FIX, as is
#: any other code (wurde_drivers.gps.quality).
_STATUS = {0: NavSatStatus.STATUS_NO_FIX, 1: NavSatStatus.STATUS_FIX, 2: NavSatStatus.STATUS_SBAS_FIX,
           3: NavSatStatus.STATUS_FIX, 4: NavSatStatus.STATUS_GBAS_FIX, 5: NavSatStatus.STATUS_GBAS_FIX}


class FixPublisher:
    """``/S/fix``: latitude, longitude (degrees) and altitude (m) with the fix's status, and a
    position covariance APPROXIMATED from HDOP and quality
    (:func:`~wurde_drivers.ros_std_covariance.fix_covariance`)."""

    def __init__(self, node: Any, stream: str) -> None:
        self.publisher = node.create_publisher(NavSatFix, std_topic(stream, 'fix'), _QOS)
        self.frame = frame_of(stream)

    def publish(self, *, latitude: float, longitude: float, altitude: float, quality: int,
                hdop: float, stamp: float) -> None:
        if not watched(self.publisher):
            return
        msg = NavSatFix()
        set_stamp(msg, stamp)
        msg.header.frame_id = self.frame
        msg.status.status = _STATUS.get(int(quality), NavSatStatus.STATUS_NO_FIX)
        msg.status.service = NavSatStatus.SERVICE_GPS
        msg.latitude, msg.longitude, msg.altitude = latitude, longitude, altitude
        msg.position_covariance = fix_covariance(quality, hdop)
        msg.position_covariance_type = NavSatFix.COVARIANCE_TYPE_APPROXIMATED
        self.publisher.publish(msg)
