"""The LaserAvoider places a scan at the odometry's pose of the scan's stamp (pluto_nav.pose_history)
and moves it to where the robot is now: a scan taken before a turn shows a box where it is now, not
where it was relative to the robot when the scan was taken.

In process: a LaserAvoider on a real CommsManager; the base's odometry and the laser supplied by a
second manager over real DDS, with stamps of the robot's clock."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest
from in_process import T0, Said, StampedRig
from wurde_core import CommsManager, Point
from wurde_core.interfaces import ObstacleAvoider

from pluto_motion.corridor_avoid import AvoidSettings
from pluto_motion.laser_avoider import MOVING, LaserAvoider


class Rig(StampedRig):
    """The avoider under test, the robot and BlindTeleop's side of the avoider."""

    def __init__(self) -> None:
        self.manager = CommsManager('laserAvoider')
        self.manager.set_no_sleep()
        self.manager.set_no_heartbeat()
        self.logger = Said('laserAvoider')
        self.module = LaserAvoider(self.manager, self.logger, AvoidSettings(), stream='StampAvoider',
                                   laser='StampLaser', ego='StampMotion', mover='StampMover', nav='StampNav')
        super().__init__('StampRobot', 'StampMotion', 'StampLaser')
        self.client = ObstacleAvoider('StampAvoider')
        self.peer.register_consumer(self.client)


@pytest.fixture
def rig(ros_domain: int) -> Iterator[Rig]:
    rig = Rig()
    try:
        rig.until(lambda: rig.odometry.peers() > 0 and rig.laser.peers() > 0, 'the avoider subscribed')
        rig.until(lambda: rig.module.fan is not None, 'the laser info taken')
        yield rig
    finally:
        rig.close()


def turned(rig: Rig, scan_stamp: float) -> np.ndarray:
    """The robot turns from heading 0 to 0.5 rad over 0.5 s (odometry at 10 Hz); a scan stamped
    ``scan_stamp`` saw a box 1 m ahead of the robot's centre.  Returns the avoider's points."""
    for i in range(6):
        rig.pose(T0 + 0.1 * i, 0.1 * i)
        rig.until(lambda: rig.module.pose is not None and math.isclose(rig.module.pose[2], 0.1 * i, abs_tol=1e-9),
                  'the pose taken')
    rig.scan(scan_stamp, 0.8)
    rig.until(lambda: rig.module.around is not None and len(rig.module.around) > 0, 'the scan taken')
    return rig.module.around



def test_a_scan_from_before_a_turn_is_moved_to_where_the_robot_is_now(rig: Rig) -> None:
    points = turned(rig, T0)                  # taken at heading 0, arrived at heading 0.5
    assert points[0] == pytest.approx((math.cos(0.5), -math.sin(0.5)), abs=1e-6)
    assert rig.module.scan_pose == pytest.approx((0.0, 0.0, 0.0))
    assert not [line for line in rig.logger.lines if 'outside the odometry' in line]


def test_between_odometry_samples_the_pose_is_interpolated(rig: Rig) -> None:
    points = turned(rig, T0 + 0.25)           # halfway between the samples at 0.2 and 0.3 rad
    assert points[0] == pytest.approx((math.cos(0.25), -math.sin(0.25)), abs=1e-6)


def test_a_scan_on_another_clock_is_placed_at_the_latest_pose_and_said_once(rig: Rig) -> None:
    points = turned(rig, 1000.0)              # a laser stamping with a clock of its own
    assert points[0] == pytest.approx((1.0, 0.0), abs=1e-6)
    rig.scan(1000.2, 0.8)
    rig.until(lambda: rig.module.laser.received() >= 2, 'the second scan taken')
    said = [line for line in rig.logger.lines if 'outside the odometry' in line]
    assert len(said) == 1, said


def test_a_scan_from_before_the_first_odometry_is_placed_when_the_odometry_comes(rig: Rig) -> None:
    """The shipped blind-teleop set-up: the laser was heard before the base, and the goal was
    asked for before either.  The avoider crashed at the first odometry (no scan placed: the
    scan had no pose to be placed at), and the MCP's restart forgot the goal."""
    rig.until(lambda: rig.client.peers('request') > 0, 'the avoider answering requests')
    rig.scan(T0, 3.0)
    rig.until(lambda: rig.module.points is not None, 'the scan taken')
    assert rig.module.scan_pose is None and rig.module.around is None
    rig.client.move_to_relative_point(Point(2.0, 0.0))
    rig.until(lambda: rig.module.pending is not None, 'the goal taken')
    rig.pose(T0 + 0.1, 0.0)
    rig.until(lambda: rig.module.state == MOVING, 'moving to the goal')
    assert rig.module.scan_pose == pytest.approx((0.0, 0.0, 0.0))
    assert rig.module.around[0] == pytest.approx((3.2, 0.0), abs=1e-6)
