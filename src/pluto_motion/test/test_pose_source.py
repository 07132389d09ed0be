"""Where the chain steers a goal (issue 38): the base odometry stands in for the localization only
in a robot without a localModule.  A goto is in the map's frame; steered on the odometry, whose
frame starts where the base did, it drives into a wall — a soak saw an avoidModule restarted
mid-goal do that before it heard the localModule.  Real DDS between two managers in one process."""

from __future__ import annotations

import time

import numpy as np
import pytest
from pluto_nav.streams import DEAD_RECKONING, STREAMS, LocPose, write_pose
from wurde_core import CommsManager, PlanarPose
from wurde_core.interfaces import Egomotion, LocalizationPose

import pluto_motion.pose_source as pose_source
from pluto_motion.pose_source import ODOMETRY, PoseSource

GRACE_S = 0.5


class Rig:
    """A PoseSource on one manager; a base (and, when asked, a localModule) on another."""

    def __init__(self) -> None:
        self.manager = CommsManager('chain')
        self.peer = CommsManager('robot')
        for m in (self.manager, self.peer):
            m.set_no_sleep()
            m.set_no_heartbeat()
        self.warnings: list[str] = []
        self.source = PoseSource(self.manager, 'RigBase', self.warnings.append, user='the goto steers')
        self.odometry = Egomotion('RigBaseMotion')
        self.peer.register_supplier(self.odometry)
        self.local: LocalizationPose | None = None

    def add_local_module(self) -> None:
        self.local = LocalizationPose(STREAMS[DEAD_RECKONING])
        self.peer.register_supplier(self.local)

    def turn(self, *, local: bool) -> tuple[float, float, float] | None:
        self.odometry.data.location = PlanarPose(1.0, 2.0, 0.0)
        self.odometry.publish_data()
        if local and self.local is not None:
            write_pose(self.local.data, LocPose(pose=(5.0, 6.0, 0.0, 0.0, 0.0, 0.0), covariance=np.eye(3),
                                                stamp=time.time()))
            self.local.publish_data()
        self.peer.step()
        self.manager.step()
        pose = self.source.pose()
        self.manager.wait(0.02)
        return pose

    def until(self, predicate, what: str, *, local: bool, timeout: float = 60.0) -> None:
        deadline = time.monotonic() + timeout
        while not predicate(self.turn(local=local)):
            assert time.monotonic() < deadline, f'{what}: not within {timeout} s'

    def close(self) -> None:
        self.peer.clean_up()
        self.manager.clean_up()


@pytest.fixture
def rig(ros_domain: int, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(pose_source, 'START_GRACE_S', GRACE_S)
    r = Rig()
    try:
        yield r
    finally:
        r.close()


def test_without_a_local_module_the_odometry_stands_in_after_the_start_grace(rig: Rig) -> None:
    rig.until(lambda pose: pose is not None, 'the odometry as the pose', local=False)
    assert rig.source.source == ODOMETRY
    assert time.monotonic() - rig.source.started >= GRACE_S
    assert any('on the base odometry' in w for w in rig.warnings)


def test_a_local_module_once_heard_is_waited_for_never_replaced_by_the_odometry(rig: Rig) -> None:
    rig.add_local_module()
    rig.until(lambda pose: pose is not None and pose[:2] == (5.0, 6.0), 'the Dead-Reckoning', local=True)
    rig.peer.unregister(rig.local)          # gone from the graph too: only "once heard" holds
    stopped = time.monotonic()
    # the localModule falls silent (killed); the odometry still flows: no pose, the robot stops
    rig.until(lambda pose: pose is None, 'the Dead-Reckoning stale', local=False)
    while time.monotonic() - stopped < 3 * GRACE_S + pose_source.FRESH_S:
        assert rig.turn(local=False) is None
    assert not any('on the base odometry' in w for w in rig.warnings)
