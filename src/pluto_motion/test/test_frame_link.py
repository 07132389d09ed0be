"""The laserAvoider sends a Navigator its goals in the Navigator's frame (pluto_motion.frame_link):
the frames of two modules' odometry can differ after a base restart (r91: 3.6 cm and 0.04 rad, the
robot stood 0.11 m from the goal for 80 s), and a map-based Navigator's frame is a map's."""

from __future__ import annotations

import math
import pathlib
import time

import pytest
from drive_fixture import program
from hypothesis import given, settings
from hypothesis import strategies as st
from pluto_motion.frame_link import STILL_M, STILL_S, FrameLink
from pluto_nav.geometry import compose, relative
from wurde_core import CommsManager, Point, Pose, Time
from wurde_core.interfaces import Egomotion, NavigatorTransport, RangeFinder
from wurde_core.wrappers import ObstacleAvoider

coordinate = st.floats(-50.0, 50.0)
angle = st.floats(-math.pi, math.pi)
poses = st.tuples(coordinate, coordinate, angle)


@settings(max_examples=200, deadline=None)
@given(transform=poses, robot=poses, point=st.tuples(coordinate, coordinate))
def test_a_standing_robot_measures_the_transform_between_the_frames(transform, robot, point) -> None:
    link = FrameLink()
    link.own(robot, 10.0)
    link.own(robot, 10.0 + STILL_S)
    assert link.other(tuple(compose(transform, robot)), 10.0 + STILL_S) is not None
    expected = compose(transform, (*point, 0.0))[:2]
    assert link.to_other(*point) == pytest.approx(tuple(expected), abs=1e-6)


def test_a_moving_robot_does_not_measure_and_keeps_the_last_transform() -> None:
    link = FrameLink()
    assert link.to_other(1.0, 2.0) == (1.0, 2.0)            # identity until measured
    link.own((0.0, 0.0, 0.0), 0.0)
    link.own((0.0, 0.0, 0.0), STILL_S)
    link.other((0.036, 0.0, 0.04), STILL_S)                  # r91's frames
    measured = link.to_other(5.0, 0.0)
    for i in range(1, 20):                                   # under way: 0.02 m a step
        link.own((0.02 * i, 0.0, 0.0), STILL_S + 0.05 * i)
        assert link.other((5.0, 5.0, 1.0), STILL_S + 0.05 * i) is None
    assert link.to_other(5.0, 0.0) == measured
    # Creeping less than STILL_M a step is standing only if it adds up to less than STILL_M.
    link.own((1.0, 0.0, 0.0), 10.0)
    for i in range(1, 11):
        link.own((1.0 + 0.9 * STILL_M * i / 10, 0.0, 0.0), 10.0 + STILL_S * i / 10)
    assert link.other((1.0, 0.0, 0.0), 10.0 + STILL_S) is not None
    link.own((1.0 + 1.1 * STILL_M, 0.0, 0.0), 10.0 + STILL_S + 0.1)
    assert link.other((1.0, 0.0, 0.0), 10.0 + 2 * STILL_S) is None


def test_the_avoider_sends_a_navigator_in_a_frame_of_its_own_goals_in_that_frame(
        ros_domain: int, tmp_path: pathlib.Path) -> None:
    """A standing robot in open space at ``odometry`` in the avoider's odometry frame; the
    Navigator (this test) reports it at ``FRAME ⊕ odometry``, as a map-based navigator would.  The
    avoider, asked for a point 1 m ahead, must ask the Navigator for a point straight ahead of the
    robot in the Navigator's frame (before, it sent the odometry frame's point: 2.4 m off)."""
    frame, odometry = (2.0, -1.0, 0.7), (1.0, 0.5, 0.3)
    navigated = tuple(float(v) for v in compose(frame, odometry))
    manager = CommsManager('FrameLinkTest')
    manager.set_no_sleep()
    ego, laser, nav = Egomotion('TestMotion'), RangeFinder('TestLaser'), NavigatorTransport('TestNav')
    ego.set_auto_timestamp(False)
    laser.set_auto_timestamp(False)
    nav.set_queue_mode(True)
    for supplier in (ego, laser, nav):
        manager.register_supplier(supplier)
    avoider = ObstacleAvoider('TestAvoider')
    manager.register_consumer(avoider)
    laser.info.max_range.set_value(8.0)
    laser.info.uniform.set_value(True)
    laser.info.theta_offset.set_value(-math.pi / 2)
    laser.info.theta_separation.set_value(math.pi / 360)
    ticks = {'n': 0}

    def world() -> None:
        """One tick of the standing robot: odometry, a scan of open space, the Navigator's status."""
        ticks['n'] += 1
        n = ticks['n']
        ego.data.location = Pose(*odometry)
        ego.data.timestamp = Time(0.1 * n)
        ego.publish_data()
        if n % 2 == 0:
            laser.data.ranges = [5.0] * 361
            laser.data.timestamp = Time(0.1 * n)
            laser.publish_data()
            laser.publish_info()
        if n % 3 == 0:
            nav.data.robot = Pose(*navigated)
            nav.publish_data()

    def until(predicate, what: str, timeout: float, process) -> None:
        deadline = time.monotonic() + timeout
        while not predicate():
            assert process.process.poll() is None, f'{what}: the avoider exited: {process.stderr}'
            assert time.monotonic() < deadline, f'{what}: not within {timeout} s; its log: {process.stderr[-800:]}'
            world()
            avoider.get_next_info()
            manager.step()
            manager.wait(0.1)

    goals: list[tuple[float, float]] = []

    def asked() -> bool:
        while nav.get_next_request():
            r = nav.requests
            if r.autonomous.get_value():
                goals.append((r.goal.get_value().x(), r.goal.get_value().y()))
        return bool(goals)

    try:
        with program('pluto_motion', 'laser_avoider', tmp_path, '-s', 'TestAvoider', '-L', 'TestLaser',
                     '-e', 'TestMotion', '-N', 'TestNav') as process:
            until(lambda: 'in the Navigator\'s frame' in process.stderr and avoider.is_connected()
                  and avoider.peers('request') > 0 and avoider.received('info') > 0,
                  'the frame measured and the avoider answering', 60, process)
            avoider.move_to_relative_point(Point(1.0, 0.0))
            until(asked, 'a goal asked of the Navigator', 30, process)
    finally:
        manager.clean_up()
    for goal in goals:
        ahead, left, _ = relative(navigated, (*goal, 0.0))
        assert 0.0 < ahead <= 1.0 + 1e-6 and abs(left) < 0.01, f'goal {goal}: {ahead:.3f} ahead, {left:.3f} left'
