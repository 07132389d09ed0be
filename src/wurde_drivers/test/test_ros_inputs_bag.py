"""A bag of a ROS 2 robot played through ros_inputs under the MCP: config/ros-robot's modules
(ros_inputs, localModule, slamModule, the drive -> avoid -> motion chain) follow the recorded
robot, and the chain's commands come out on its cmd_vel.

The bag (:mod:`ros_inputs_bag`) is written by the test from the simulated office and played by
wurde_mcp's ``replay``; its odometry's heading drifts, so the Pose can only stay near the truth if
slamModule corrects it from the scans.
"""

from __future__ import annotations

import math
import os
import pathlib
from typing import Any

import pytest
import rclpy
from geometry_msgs.msg import Twist
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from ros_inputs_bag import BEAMS, write_bag
from sim_fixture import Observer
from wurde_testing import ChildProcess, find_executable

ROOT = pathlib.Path(__file__).resolve().parents[3]
SHIPPED = ROOT / 'config' / 'ros-robot'
DR, LASER_DR, POSE = ('Localization/Dead-Reckoning', 'Localization/Laser_Dead-Reckoning',
                      'Localization/Pose')
STREAMS = {DR: 'LocalizationPose', LASER_DR: 'LocalizationPose', POSE: 'LocalizationPose',
           'slam/status': 'FVectorState', 'PlutoLaser': 'RangeFinder',
           'avoidance/command': 'ActuatorState'}
#: The modules each read (ROS topics of the WURDE streams) before the bag may start.
READERS = {'localModule': '/wurde/PlutoBaseMotion/data', 'slamModule': '/wurde/PlutoLaser/data'}


def _reads(node: Any, module: str, topic: str) -> bool:
    try:
        return topic in {name for name, _ in node.get_subscriber_names_and_types_by_node(module, '/')}
    except Exception:       # the node is not in the graph yet
        return False


def _heading_error(a: float, b: float) -> float:
    return abs(math.remainder(a - b, math.tau))


def test_a_bag_played_through_ros_inputs_is_followed_by_localization_slam_and_the_chain(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    for name in ('mcp-config.xml', 'mcp-mappings.xml'):
        (tmp_path / name).write_bytes((SHIPPED / name).read_bytes())
    bag = write_bag(tmp_path / 'robot.mcap')
    env = dict(os.environ, WURDE_CONFIG_DIR=str(tmp_path), WURDE_LOG_DIRECTORY=str(tmp_path),
               WURDE_DATA_DIR=str(tmp_path))
    observer = Observer(STREAMS)
    context = Context()
    rclpy.init(context=context)
    node = rclpy.create_node('test_cmd_vel', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    twists: list[tuple[float, float]] = []
    node.create_subscription(Twist, '/cmd_vel', lambda m: twists.append((m.linear.x, m.angular.z)), 50)

    def until(predicate: Any, what: str, timeout: float = 60.0) -> None:
        observer.until(lambda o: (executor.spin_once(timeout_sec=0.0), predicate())[1], what, timeout)

    try:
        with ChildProcess([find_executable('wurde_mcp', 'mcp'), '-c', str(tmp_path / 'mcp-config.xml'),
                           '-m', str(tmp_path / 'mcp-mappings.xml'), '-a'], env=env) as mcp:
            mcp.expect('MCP ready', timeout=60)
            until(lambda: all(_reads(observer.manager.node, m, t) for m, t in READERS.items())
                  and any(list(m.element)[:1] == [1] for _, m in observer.events['slam/status']),
                  'the modules up, slamModule running')
            with ChildProcess([find_executable('wurde_mcp', 'replay'), str(tmp_path / 'robot.mcap'),
                               '-w', '30', '-n', 'ros_inputs'], env=env) as replay:
                until(lambda: replay.process.poll() is not None, 'the bag played', timeout=60)
                assert replay.stop() == 0, replay.stderr
            assert f'replay: {bag.messages} messages' in replay.stdout, replay.stdout
            until(lambda: len(observer.events[LASER_DR]) >= len(bag.scan_centres) - 2,
                  'a Laser_Dead-Reckoning pose per scan', timeout=20)
            # the chain commands the robot through ros_inputs: a velocity to the avoidModule comes
            # out of the driveModule as the base's command, and as a Twist on the robot's cmd_vel
            until(lambda: observer.obj('avoidance/command').peers() > 0, 'the avoidModule')
            observer.request('avoidance/command', cmd_flags=0, velocity=[0.2, 0.0])
            until(lambda: any(tv > 0.0 for tv, _ in twists), 'a Twist from the chain', timeout=20)
            assert mcp.stop(timeout=30) == 0, mcp.stdout[-3000:]
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.shutdown(context=context)
        observer.close()
    # one Laser_Dead-Reckoning pose per scan heard, at the scan's centre (the stamps the bag's)
    centres = set(round(c, 4) for c in bag.scan_centres)
    laser_stamps = [s for s, _ in observer.events[LASER_DR]]
    assert all(round(s, 4) in centres for s in laser_stamps), laser_stamps[:5]
    assert len(set(laser_stamps)) == len(laser_stamps)
    scans = observer.events['PlutoLaser']
    assert scans and all(len(m.ranges) == BEAMS for _, m in scans)
    assert all(round(s, 4) in centres for s, _ in scans)
    # dead reckoning is the odometry (from the origin: no map); the Pose follows the truth
    final_stamp, final_dr = observer.events[DR][-1]
    odometry = {round(s, 4): (x, y, t) for s, x, y, t in bag.odometry}
    x, y, theta = odometry[round(final_stamp, 4)]
    assert (final_dr.pose.x, final_dr.pose.y) == pytest.approx((x, y), abs=1e-3)
    truth = bag.truth_at(final_stamp)
    dr_error = math.hypot(x - truth[0], y - truth[1])
    assert dr_error > 0.3                            # the drift slamModule has to take out
    stamp, pose = observer.events[POSE][-1]
    true = bag.truth_at(stamp)
    error = math.hypot(pose.pose.x - true[0], pose.pose.y - true[1])
    assert pose.cmd_flags == 2, pose                 # slamModule holds the setter
    assert error < 0.5 * dr_error, (error, dr_error)
    assert _heading_error(pose.pose.theta, true[2]) < math.radians(5)
    status = observer.events['slam/status'][-1][1]
    assert status.element[2] >= len(bag.scan_centres) // 2, list(status.element)
    for module in ('ros_inputs', 'localModule', 'slamModule', 'driveModule', 'avoidModule', 'motionModule'):
        log = (tmp_path / 'mcp-modules' / f'{module}.log').read_text()
        assert log.rstrip().endswith('--- exit code 0'), f'{module}: {log[-2000:]}'
        assert 'Traceback' not in log, f'{module}: {log[-2000:]}'
    ros_inputs_log = (tmp_path / 'mcp-modules' / 'ros_inputs.log').read_text()
    assert 'upside down' in ros_inputs_log and f'{BEAMS} beams' in ros_inputs_log
    # only the bag speaks on the robot's topics (the localModule's odom is remapped away)
    assert 'nodes publish' not in ros_inputs_log, ros_inputs_log[-2000:]
