"""ros_inputs as a real process against a test-side "robot" (an rclpy node publishing LaserScan,
Odometry and /tf_static, reading cmd_vel) and a WURDE consumer of the streams it supplies."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
import rclpy
from geometry_msgs.msg import TransformStamped, Twist
from nav_msgs.msg import Odometry
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from scipy.spatial.transform import Rotation
from sensor_msgs.msg import LaserScan
from sim_fixture import Observer, heartbeat
from tf2_msgs.msg import TFMessage
from wurde_core import RunState
from wurde_core.ros_messages import set_stamp
from wurde_testing import ChildProcess, find_executable

WAIT_S = 30.0
BEAMS, FOV = 1081, math.radians(270.0)
STEP = FOV / (BEAMS - 1)
RANGE_MIN, RANGE_MAX = 0.02, 30.0
TIME_INCREMENT = 2.5e-5
#: The first beams: NaN, +inf, -inf, range_max, beyond it, below range_min, range_min; then a ramp.
SPECIAL = [math.nan, math.inf, -math.inf, RANGE_MAX, 35.0, 0.01, RANGE_MIN]
SPECIAL_OUT = [math.nan, math.inf, math.nan, math.inf, math.inf, math.nan, RANGE_MIN]
#: base_link -> mount (ahead, up, turned 0.3 rad) -> laser (upside down): through two frames.
MOUNT = (0.2, 0.0, 0.3, 0.3)
LASER = (0.1, 0.0, 0.05)
LASER_XYZ = (0.2 + 0.1 * math.cos(0.3), 0.1 * math.sin(0.3), 0.35)
T0 = 1_000.0
ARGS = ['-p', 'silent_after:=0.3', '-p', 'cmd_rate:=20.0', '-p', 'max_held_scans:=5',
        '-p', 'max_tv:=1.0']
#: The command watchdog's timeout (s): long enough that a stop within it is not the watchdog's.
TIMEOUT_S = 2.0


def ramp() -> list[float]:
    return SPECIAL + [1.0 + 0.001 * i for i in range(len(SPECIAL), BEAMS)]


def scan_message(stamp: float) -> LaserScan:
    message = LaserScan()
    set_stamp(message, stamp)
    message.header.frame_id = 'laser'
    message.angle_min, message.angle_max, message.angle_increment = -FOV / 2, FOV / 2, STEP
    message.time_increment, message.scan_time = TIME_INCREMENT, 0.1
    message.range_min, message.range_max = RANGE_MIN, RANGE_MAX
    message.ranges = ramp()
    return message


def odometry_message(stamp: float, x: float, y: float, theta: float, tv: float, rv: float) -> Odometry:
    message = Odometry()
    set_stamp(message, stamp)
    message.header.frame_id, message.child_frame_id = 'odom', 'base_link'
    message.pose.pose.position.x, message.pose.pose.position.y = x, y
    message.pose.pose.orientation.z, message.pose.pose.orientation.w = math.sin(theta / 2), math.cos(theta / 2)
    message.twist.twist.linear.x, message.twist.twist.angular.z = tv, rv
    return message


def edge(parent: str, child: str, xyz: tuple[float, float, float],
         rpy: tuple[float, float, float]) -> TransformStamped:
    t = TransformStamped()
    t.header.frame_id, t.child_frame_id = parent, child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = xyz
    q = Rotation.from_euler('xyz', rpy).as_quat()
    t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z, t.transform.rotation.w = q
    return t


class Robot:
    """The test's ROS robot: publishers of its sensors, a reader of its cmd_vel."""

    def __init__(self, context: Any) -> None:
        self.node = rclpy.create_node('test_robot', context=context)
        self.executor = SingleThreadedExecutor(context=context)
        self.executor.add_node(self.node)
        best_effort = QoSProfile(depth=20, reliability=ReliabilityPolicy.BEST_EFFORT)
        self.scan = self.node.create_publisher(LaserScan, '/scan', best_effort)   # as many drivers
        self.odom = self.node.create_publisher(Odometry, '/odom', 20)
        self.tf_static = self.node.create_publisher(TFMessage, '/tf_static', QoSProfile(
            depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL))
        self.mirror: list[LaserScan] = []      # ros_inputs' standard /PlutoLaser/scan
        self.node.create_subscription(LaserScan, '/PlutoLaser/scan', self.mirror.append, 20)
        # (when ros_inputs wrote it: the DDS source timestamp, s; tv, rv).  Not the arrival: a
        # test process that spins late takes the first Twists late and the span looks short.
        self.twists: list[tuple[float, float, float]] = []
        self.cmd_vel = self.node.create_subscription(
            Twist, '/cmd_vel', lambda m, info: self.twists.append(
                (info['source_timestamp'] * 1e-9, m.linear.x, m.angular.z)), 20)

    def spin(self) -> None:
        self.executor.spin_once(timeout_sec=0.0)

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()


def until(observer: Observer, robot: Robot, predicate: Callable[[], bool], what: str,
          timeout: float = WAIT_S, every: Callable[[], None] | None = None) -> None:
    deadline = time.monotonic() + timeout
    while True:
        observer.pump()
        robot.spin()
        if predicate():
            return
        if time.monotonic() > deadline:
            counts = {s: len(e) for s, e in observer.events.items()}
            raise AssertionError(f'{what}: not within {timeout} s; events {counts}, twists '
                                 f'{robot.twists[-5:]}')
        if every is not None:
            every()
        observer.manager.wait(0.02)


def logged(child: ChildProcess, text: str) -> Callable[[], bool]:
    return lambda: text in child.stderr


def said(child: ChildProcess, text: str) -> int:
    """How often the module's logger said ``text`` (its own lines, not rclpy's copies on /rosout)."""
    return sum(1 for line in child.stderr.splitlines()
               if line.startswith('[') and '] ros_inputs: ' in line and text in line)


@pytest.fixture
def robot(rclpy_context: Any) -> Iterator[Robot]:
    value = Robot(rclpy_context)
    try:
        yield value
    finally:
        value.close()


def ros_inputs(*args: str) -> ChildProcess:
    return ChildProcess([find_executable('wurde_drivers', 'ros_inputs'), '--ros-args', *ARGS, *args])


def test_scans_odometry_and_the_mount_become_the_laser_and_base_streams(robot: Robot) -> None:
    observer = Observer({'PlutoLaser': 'RangeFinder', 'PlutoLaser/RWI': 'RangeFinder',
                         'PlutoLaser/Timing': 'FVectorState', 'PlutoBaseMotion': 'Egomotion',
                         **heartbeat('ros_inputs')})
    try:
        with ros_inputs() as child:
            until(observer, robot, lambda: robot.scan.get_subscription_count() > 0
                  and robot.odom.get_subscription_count() > 0
                  and all(observer.obj(s).peers() > 0 for s in ('PlutoLaser', 'PlutoLaser/Timing',
                                                                 'PlutoBaseMotion')),
                  'ros_inputs and the test matched')
            # Odometry (sent until heard: the base frame comes from its child_frame_id)
            until(observer, robot, lambda: len(observer.events['PlutoBaseMotion']) > 0, 'odometry',
                  every=lambda: robot.odom.publish(odometry_message(T0, 1.0, 2.0, 0.5, 0.3, 0.1)))
            stamp, motion = observer.events['PlutoBaseMotion'][0]
            assert stamp == pytest.approx(T0, abs=1e-6)
            assert (motion.location.x, motion.location.y, motion.location.theta) == pytest.approx((1.0, 2.0, 0.5))
            assert (motion.tv, motion.rv) == pytest.approx((0.3, 0.1))
            # Seven scans before the mount is known: the newest five are held
            until(observer, robot, logged(child, 'holding the newest 5 scans'), 'scans held',
                  every=lambda: robot.scan.publish(scan_message(T0 - 1.0)))
            sent = [T0 + 0.1 * i for i in range(7)]
            for when in sent:
                robot.scan.publish(scan_message(when))
            observer.quiet_span('ros_inputs', 'ros_inputs takes the scans in', turns=3)
            assert observer.events['PlutoLaser'] == []
            robot.tf_static.publish(TFMessage(transforms=[
                edge('base_link', 'mount', MOUNT[:3], (0.0, 0.0, MOUNT[3])),
                edge('mount', 'laser', LASER, (math.pi, 0.0, 0.0))]))
            centres = [when + (BEAMS - 1) / 2 * TIME_INCREMENT for when in sent]
            until(observer, robot, lambda: len(observer.events['PlutoLaser/Timing']) >= 5
                  and len(observer.events['PlutoLaser/RWI']) >= 5 and 'PlutoLaser' in observer.infos,
                  'the held scans')
            assert 'publishing 5 held scans' in child.stderr, child.stderr
            assert [s for s, _ in observer.events['PlutoLaser']] == pytest.approx(centres[2:], abs=2e-6)
            assert [s for s, _ in observer.events['PlutoLaser/Timing']] == pytest.approx(centres[2:], abs=2e-6)
            assert [s for s, _ in observer.events['PlutoLaser/RWI']] == pytest.approx(
                [when + (BEAMS - 1) * TIME_INCREMENT for when in sent[2:]], abs=2e-6)
            assert all(list(m.element) == [BEAMS] for _, m in observer.events['PlutoLaser/Timing'])
            # upside down: the robot's counter-clockwise order is the laser's reversed
            want = list(reversed(ramp()))
            want[-len(SPECIAL):] = list(reversed(SPECIAL_OUT))
            for _, scan in observer.events['PlutoLaser'] + observer.events['PlutoLaser/RWI']:
                assert len(scan.ranges) == BEAMS
                for index, (got, expected) in enumerate(zip(scan.ranges, want)):
                    if math.isnan(expected):
                        assert math.isnan(got), index
                    else:
                        assert got == pytest.approx(expected, rel=1e-6), index
            for stream in ('PlutoLaser', 'PlutoLaser/RWI'):
                info = observer.infos[stream]
                xyz = (info.x_offset, info.y_offset, info.z_offset)
                assert xyz == pytest.approx(LASER_XYZ, abs=1e-6)        # float32
                # the laser's last beam (+135 deg) points to 0.3 - 135 deg on the robot
                assert info.theta_offset == pytest.approx(0.3 - FOV / 2, abs=1e-6)
                assert info.theta_separation == pytest.approx(STEP, rel=1e-6)
                assert info.max_range == pytest.approx(RANGE_MAX) and info.uniform
            # the standard mirror: the same fan, in frame PlutoLaser (at the mount, no yaw)
            until(observer, robot, lambda: len(robot.mirror) >= 5, 'the scans on /PlutoLaser/scan')
            mirror = robot.mirror[-1]
            assert mirror.header.frame_id == 'PlutoLaser' and len(mirror.ranges) == BEAMS
            assert mirror.angle_min == pytest.approx(0.3 - FOV / 2, abs=1e-6)
            assert mirror.angle_increment == pytest.approx(STEP, rel=1e-6)
            assert mirror.angle_max == pytest.approx(0.3 + FOV / 2, abs=1e-5)
            # silence is said once per topic; the scans' return too
            until(observer, robot, lambda: 'LaserScan on /scan silent' in child.stderr
                  and 'Odometry on /odom silent' in child.stderr, 'the silence logged')
            until(observer, robot, logged(child, 'LaserScan on /scan is back'), 'the scans back',
                  every=lambda: robot.scan.publish(scan_message(T0 + 5.0)))
            assert said(child, 'LaserScan on /scan silent') == 1, child.stderr
            assert child.stop() == 0, child.stderr
    finally:
        observer.close()


def test_drive_requests_come_out_as_twists_and_stop_when_they_stop(robot: Robot) -> None:
    observer = Observer({'PlutoBaseDrive': 'RobotDrive', 'PlutoBaseCommand': 'ActuatorState',
                         **heartbeat('ros_inputs')})
    try:
        with ros_inputs('-p', f'command_timeout:={TIMEOUT_S}') as child:
            until(observer, robot, lambda: observer.obj('PlutoBaseDrive').peers() > 0
                  and observer.obj('PlutoBaseCommand').peers() > 0
                  and robot.cmd_vel.get_publisher_count() > 0, 'ros_inputs and the test matched')
            assert robot.twists == []           # no command, no Twist: a stopped robot is left alone
            observer.request('PlutoBaseDrive', trans_velocity=5.0, rot_velocity=0.2)   # once
            until(observer, robot, lambda: any(tv == 0.0 for _, tv, _ in robot.twists[1:]),
                  'the twists, then the watchdog\'s stop')
            moving = [(tv, rv) for _, tv, rv in robot.twists if tv != 0.0]
            # clamped to max_tv; sent again at cmd_rate (20 Hz) until the watchdog stopped it
            assert set(moving) == {(1.0, 0.2)} and len(moving) >= 10, robot.twists
            stops = [index for index, (_, tv, rv) in enumerate(robot.twists) if (tv, rv) == (0.0, 0.0)]
            assert stops == [len(robot.twists) - 1], robot.twists
            span = robot.twists[-1][0] - robot.twists[0][0]
            assert TIMEOUT_S - 0.1 <= span <= TIMEOUT_S + 8.0, span
            # The module's log line comes through its stderr pipe, maybe after the Twist (a fresh
            # clone's make test once read stderr before it).
            until(observer, robot, lambda: said(child, 'no command for') >= 1, "the watchdog's log line")
            assert said(child, 'no command for') == 1
            seen = len(robot.twists)
            observer.quiet_span('ros_inputs', 'ros_inputs after the stop', turns=3)
            robot.spin()
            assert len(robot.twists) == seen, robot.twists[seen:]
            # Pluto's base command; then the module ends while the robot moves: a stop goes out
            observer.request('PlutoBaseCommand', cmd_flags=0, velocity=[0.3, -0.1])
            until(observer, robot, lambda: robot.twists[-1][1:] == pytest.approx((0.3, -0.1)),
                  'the Pluto command as a Twist')
            observer.request('PlutoBaseCommand', cmd_flags=0, velocity=[0.3, -0.1])   # the watchdog afresh
            # Idle (as the MCP commands it) stops the robot; back in Run it takes commands again
            observer.request('heartbeat/ros_inputs', state=RunState.IDLE)
            until(observer, robot, lambda: robot.twists[-1][1:] == (0.0, 0.0), 'the stop when Idle')
            assert said(child, 'no command for') == 1       # the stop was Idle's, not the watchdog's
            observer.request('heartbeat/ros_inputs', state=RunState.RUN)
            until(observer, robot, lambda: robot.twists[-1][1:] == pytest.approx((0.3, -0.1)),
                  'a command after Idle', every=lambda: observer.request('PlutoBaseCommand', cmd_flags=0,
                                                                         velocity=[0.3, -0.1]))
            assert child.stop() == 0, child.stderr
            until(observer, robot, lambda: robot.twists[-1][1:] == (0.0, 0.0), 'the stop at the end',
                  timeout=5.0)
    finally:
        observer.close()


@pytest.mark.parametrize('parameter, reason', [
    ('cmd_vel_topic:=/PlutoBase/cmd_vel', 'parameter cmd_vel_topic: /PlutoBase/cmd_vel is this '
                                          'module\'s own standard topic'),
    ('scan_topic:=/PlutoLaser/scan', 'parameter scan_topic: /PlutoLaser/scan is this module'),
    ('max_tv:=-1.0', 'parameter max_tv: -1.0 is out of range'),
    ('base_frame:=3', 'parameter base_frame: 3 is not a text'),
    ('odom_topic:=bad topic', 'parameter odom_topic: \'bad topic\' is not a valid topic name')])
def test_bad_parameters_are_refused_with_their_name(ros_domain: int, parameter: str, reason: str) -> None:
    with ChildProcess([find_executable('wurde_drivers', 'ros_inputs'), '--ros-args', '-p', parameter]) as child:
        assert child.process.wait(timeout=WAIT_S) == 2
        child.stop()
    assert f'ros_inputs: {reason}' in child.stderr, child.stderr
    assert 'Traceback' not in child.stderr
