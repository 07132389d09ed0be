"""The avoidModule places each laser scan at the pose of the scan's stamp, in a frame that never
jumps (Dead-Reckoning, else the base odometry: :meth:`pluto_motion.pose_source.PoseSource.frame`),
and moves it to where the robot is now in that frame: a correction of Localization/Pose by a pose
setter is not motion, and the robot's turn while the scan was on its way is.

In process: an AvoidModule on a real CommsManager; the base's odometry, the localModule's streams
and the laser supplied by a second manager over real DDS, with stamps of the robot's clock."""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np
import pytest
from in_process import T0, Said, StampedRig
from pluto_nav.streams import DEAD_RECKONING, POSE, POSE_SETTER, POST_POSE, STREAMS, LocPose, write_pose
from wurde_core import CommsManager
from wurde_core.interfaces import LocalizationPose

from pluto_motion.avoid_control import AvoidController, _relative
from pluto_motion.avoid_module import AvoidModule


class Rig(StampedRig):
    """The avoidModule under test and a robot with the localModule's streams."""

    def __init__(self) -> None:
        self.manager = CommsManager('avoidModule')
        self.manager.set_no_sleep()
        self.manager.set_no_heartbeat()
        self.logger = Said('avoidModule')
        self.module = AvoidModule(self.manager, self.logger, AvoidController(), base='StampBase',
                                  laser='StampScanner')
        self.loc = {n: LocalizationPose(STREAMS[n]) for n in (DEAD_RECKONING, POSE, POST_POSE)}
        super().__init__('StampRobot', 'StampBaseMotion', 'StampScanner', tuple(self.loc.values()))

    def localization(self, stamp: float, dead_reckoning: tuple[float, float, float],
                     pose: tuple[float, float, float]) -> None:
        """The localModule's (0) and (3), the setter poseModule's."""
        for n, (x, y, theta) in ((DEAD_RECKONING, dead_reckoning), (POSE, pose)):
            write_pose(self.loc[n].data, LocPose(pose=(x, y, 0.0, theta, 0.0, 0.0), setter=POSE_SETTER,
                                                 covariance=np.eye(3) * 1e-4, stamp=stamp))
            self.loc[n].publish_data()

    def box(self) -> np.ndarray:
        """Where the avoid thread sees the scan's nearest point now (robot frame)."""
        module = self.module
        points, then = module.control.laser
        seen = _relative(points, then, module.pose.poses[module.frame_source])
        return seen[np.argmin(np.hypot(points[:, 0], points[:, 1]))]


@pytest.fixture
def rig(ros_domain: int) -> Iterator[Rig]:
    rig = Rig()
    try:
        rig.until(lambda: rig.odometry.peers() > 0 and rig.laser.peers() > 0
                  and all(obj.peers() > 0 for obj in rig.loc.values()), 'the avoidModule subscribed')
        rig.until(lambda: rig.module.laser_info, 'the laser info taken')
        yield rig
    finally:
        rig.close()


def test_a_scan_from_before_a_turn_is_moved_to_where_the_robot_is_now(rig: Rig) -> None:
    """No localModule: the base odometry is the frame.  The robot turns from heading 0 to 0.5 rad
    over 0.5 s; a scan stamped at the start arrives at the end, with a box 1 m ahead of the
    centre: the box is 1 m along the old heading, seen from the new one."""
    for i in range(6):
        rig.pose(T0 + 0.1 * i, 0.1 * i)
        rig.until(lambda: rig.module.pose.poses.get('odometry', (0.0, 0.0, -1.0))[2] == pytest.approx(0.1 * i),
                  'the odometry taken')
    assert rig.module.frame_source == 'odometry'
    rig.scan(T0, 0.8)
    rig.until(lambda: rig.module.control.laser[0].shape[0] > 0, 'the scan taken')
    assert rig.module.control.laser[1] == pytest.approx((0.0, 0.0, 0.0))
    assert rig.box() == pytest.approx((math.cos(0.5), -math.sin(0.5)), abs=1e-6)
    assert not [line for line in rig.logger.lines if 'outside the stamps' in line]


def test_a_correction_of_the_pose_is_not_taken_for_motion(rig: Rig) -> None:
    """The localModule runs with poseModule setting: the scan is placed in Dead-Reckoning, which
    never jumps; when poseModule moves Localization/Pose by 0.3 m the robot has not moved, and
    neither has the box in front of it (moved with the Pose, it came 0.3 m nearer)."""
    rig.loc[POST_POSE].info.cmd_flags.set_value(POSE_SETTER)     # transient local: heard once matched
    rig.loc[POST_POSE].publish_info()
    rig.until(lambda: rig.module.pose.loc.setter == POSE_SETTER, 'the setter heard')
    for i in range(3):
        rig.localization(T0 + 0.1 * i, (1.0, 2.0, 0.0), (5.0, 5.0, 0.0))
    rig.until(lambda: rig.module.frame_source == 'Localization/Dead-Reckoning'
              and rig.module.pose.source == 'Localization/Pose', 'the localization taken')
    rig.scan(T0 + 0.2, 0.8)
    rig.until(lambda: rig.module.control.laser[0].shape[0] > 0, 'the scan taken')
    assert rig.module.control.laser[1] == pytest.approx((1.0, 2.0, 0.0))
    rig.localization(T0 + 0.3, (1.0, 2.0, 0.0), (5.3, 5.0, 0.0))
    rig.until(lambda: rig.module.pose.poses['Localization/Pose'][0] == pytest.approx(5.3), 'the correction taken')
    assert rig.box() == pytest.approx((1.0, 0.0), abs=1e-6)
