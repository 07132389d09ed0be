"""Which reason a failed drive gets (issue 13).  A chain whose base died can fail before the
navigator counts the base down — its pose stale, its goto stuck, its plan "unreachable" (make test
r96: stop reason 3 and "unreachable" in the log, the base killed 5 s before).  The navigator
judges a chain failure at once while the base's odometry flows; while the base is quiet it holds
the failure until the base is down (failed: the base) or heard again (failed: the chain's reason).

In process: a NavigatorModule on a real CommsManager, the base's odometry supplied by a second
manager over real DDS, and the chain's failure as the Task handle a MotionProxy returns."""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest
from rclpy.parameter import Parameter
import in_process
from wurde_core import CommsManager, Pose
from wurde_core.interfaces import Egomotion
from wurde_core.heartbeat import RESTART_ENV
from wurde_core.resume import STATE_ENV
from wurde_core.wrappers import STOP_FAILED, STOP_NONE

from pluto_motion.navigator import BASE_QUIET_S, NavigatorModule
from pluto_motion.task import Task, TaskResult

BASE_WAIT = 2.0


class Said(in_process.Said):
    """The navigator's Logger, keeping what it was told to log."""

    def __init__(self) -> None:
        super().__init__('navigator')

    def failures(self) -> list[str]:
        return [line for line in self.lines if 'not reached' in line]


class Rig(in_process.ModuleRig):
    """The navigator under test and a base whose odometry can be switched off."""

    def __init__(self) -> None:
        self.manager = CommsManager('navigator')
        self.manager.set_no_sleep()
        self.manager.set_no_heartbeat()
        self.logger = Said()
        self.module = NavigatorModule(self.manager, self.logger, {}, 'JudgedNavigator', 300.0, base='JudgedBase')
        self.peer = CommsManager('JudgedBase')
        self.peer.set_no_sleep()
        self.peer.set_no_heartbeat()
        self.odometry = Egomotion('JudgedBaseMotion')
        self.peer.register_supplier(self.odometry)
        self.flowing = True

    def feed(self) -> None:
        if self.flowing:
            self.odometry.data.location = Pose(1.0, 2.0, 0.0)
            self.odometry.publish_data()

    def driving(self, result: list[TaskResult]) -> None:
        """Autonomous towards (3, 3), the chain's task answering ``result[0]`` ('unreachable')."""
        assert self.module._heard, 'the base was heard before the drive'
        self.module.goal, self.module.autonomous = (3.0, 3.0), True
        self.module.task = Task(lambda: (result[0], 'unreachable'), lambda: None)

    def failing_while_quiet(self) -> None:
        """Driving, the base falls quiet, then the chain fails: the failure is held."""
        result = [TaskResult.UNKNOWN]
        self.driving(result)
        self.flowing = False
        self.until(lambda: time.monotonic() - self.module._odometry_at > BASE_QUIET_S, 'the base quiet')
        result[0] = TaskResult.FAILED
        self.turn()
        assert self.module.autonomous and self.module.task is None, 'a failure while the base is quiet is held'

    def close(self) -> None:
        self.peer.clean_up()
        self.manager.clean_up()


@pytest.fixture
def rig(ros_domain: int) -> Iterator[Rig]:
    r = Rig()
    try:
        r.manager.step()
        assert r.manager.node.set_parameters([Parameter('base_wait', value=BASE_WAIT)])[0].successful
        r.until(lambda: r.module._heard, 'the base\'s first odometry')
        yield r
    finally:
        r.close()


def test_a_chain_failure_while_the_base_flows_is_the_chains(rig: Rig) -> None:
    rig.driving([TaskResult.FAILED])
    rig.until(lambda: not rig.module.autonomous, 'the failure judged')
    assert rig.module.stop_reason == STOP_FAILED
    assert rig.logger.failures() == ['navigator: goal (3.0, 3.0) not reached: unreachable']


def test_a_chain_failure_while_the_base_is_quiet_waits_for_the_base(rig: Rig) -> None:
    rig.failing_while_quiet()
    rig.until(lambda: not rig.module.autonomous, 'the base down')
    assert rig.module.stop_reason == STOP_FAILED
    said = rig.logger.failures()
    assert len(said) == 1 and 'not reached: the base is down: no odometry from JudgedBase for' in said[0], said


def test_a_held_failure_gets_the_chains_reason_when_the_base_is_heard_again(rig: Rig) -> None:
    rig.failing_while_quiet()
    rig.flowing = True
    rig.until(lambda: not rig.module.autonomous, 'the failure judged')
    assert rig.module.stop_reason == STOP_FAILED
    assert rig.logger.failures() == ['navigator: goal (3.0, 3.0) not reached: unreachable']


def test_a_chain_that_lost_the_goal_gets_it_again(rig: Rig) -> None:
    """A moveto that failed for another reason than the map's (the motion thread stopped: a link
    restarted) is sent again: the navigator stays autonomous and reports neither reached nor
    failed (issue 38)."""
    rig.module._deadline = time.monotonic() + 300.0
    rig.module.goal, rig.module.autonomous = (3.0, 3.0), True
    rig.module.task = Task(lambda: (TaskResult.FAILED, 'motion thread stopped'), lambda: None)
    rig.until(lambda: rig.module.retries == 1 and rig.module.task is not None, 'the goal sent again')
    assert rig.module.autonomous and rig.module.stop_reason == STOP_NONE
    assert rig.module.task.result() is TaskResult.UNKNOWN     # the new moveto, waiting for its echo
    assert rig.logger.failures() == []
    assert any('sending it again' in line for line in rig.logger.lines)


def test_a_lost_goal_whose_time_is_up_fails(rig: Rig) -> None:
    rig.module._deadline = time.monotonic() - 1.0
    rig.module.goal, rig.module.autonomous = (3.0, 3.0), True
    rig.module.task = Task(lambda: (TaskResult.FAILED, 'motion thread stopped'), lambda: None)
    rig.until(lambda: not rig.module.autonomous, 'the failure judged')
    assert rig.module.stop_reason == STOP_FAILED and rig.module.retries == 0


def test_a_restarted_navigator_resumes_its_goal(ros_domain: int, tmp_path, monkeypatch) -> None:
    """The goal and its time left are in the resume file the MCP gives the navigator; the next
    process (a restart) drives to it again at once."""
    monkeypatch.setenv(STATE_ENV, str(tmp_path / 'navigator.resume'))
    first = Rig()
    try:
        first.manager.step()
        first.module._set_goal(3.0, 3.0, 'test')
        first.module.autonomous, first.module._deadline = True, time.monotonic() + 100.0
        first.module._drive()
    finally:
        first.close()
    monkeypatch.setenv(RESTART_ENV, '1')
    second = Rig()
    try:
        assert second.module.goal == (3.0, 3.0) and second.module.autonomous
        assert 0 < second.module._deadline - time.monotonic() <= 100.0
        second.until(lambda: second.module.task is not None, 'the goal driven to again')
        assert second.module.stop_reason == STOP_NONE
        assert any('resuming the goal (3.0, 3.0)' in line for line in second.logger.lines)
    finally:
        second.close()
