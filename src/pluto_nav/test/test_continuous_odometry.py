"""ContinuousOdometry: a consumer's odometry frame outlives restarts of the base."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pluto_nav.continuous_odometry import ContinuousOdometry
from pluto_nav.geometry import compose, relative
from wurde_core import Pose, Time
from wurde_core.interfaces import Egomotion


def _sample(pose: tuple[float, float, float], stamp: float, sequence: int, session: int = 0):
    data = Egomotion('Base').data
    data.location = Pose(*pose)
    data.timestamp = Time(stamp)
    data.ros_message().header.sequence = sequence
    data.ros_message().header.session = session
    return data


def test_odometry_that_never_restarts_is_passed_through() -> None:
    odometry = ContinuousOdometry()
    for i in range(1, 50):
        pose = (0.05 * i, 0.01 * i, math.remainder(0.02 * i, math.tau))
        assert odometry.take(_sample(pose, 0.1 * i, i)) == pytest.approx(pose)
    assert odometry.resets == 0


def test_a_new_base_process_from_zero_goes_on_from_the_last_pose() -> None:
    """The base restarts at rest (however long it was down: the jump is slow) with its odometry at
    zero: the consumer's pose goes on from where it was, and the new process's motion is added in
    the old frame."""
    odometry = ContinuousOdometry()
    odometry.take(_sample((0.0, 0.0, 0.0), 1.0, 1))
    odometry.take(_sample((1.0, 0.2, math.pi / 2), 2.0, 2))
    assert odometry.take(_sample((0.0, 0.0, 0.0), 60.0, 1)) == pytest.approx((1.0, 0.2, math.pi / 2))
    # 0.5 m ahead of the restarted base is 0.5 m along +y of the old frame (it faced +y).
    assert odometry.take(_sample((0.5, 0.0, 0.0), 61.0, 2)) == pytest.approx((1.0, 0.7, math.pi / 2))
    assert odometry.resets == 1


def test_a_new_process_is_known_by_its_session_whatever_its_count() -> None:
    """The make-test failure: the consumer was held Idle while the base restarted, and the first
    sample it took of the new process (standing where the old one stopped, 4 s later) was numbered
    past the old process's last one, a jump slow enough for a robot.  The session tells."""
    odometry = ContinuousOdometry()
    for i in range(1, 40):
        odometry.take(_sample((0.025 * i, 0.0, -0.017 * i), 0.1 * i, i, session=77))
    last = odometry.pose
    assert odometry.take(_sample((0.0, 0.0, 0.0), 8.0, 41, session=5)) == pytest.approx(last)
    assert odometry.resets == 1
    # Without sessions (a sender that does not say), the same samples are taken for motion.
    blind = ContinuousOdometry()
    for i in range(1, 40):
        blind.take(_sample((0.025 * i, 0.0, -0.017 * i), 0.1 * i, i))
    assert blind.take(_sample((0.0, 0.0, 0.0), 8.0, 41)) == pytest.approx((0.0, 0.0, 0.0))
    assert blind.resets == 0


def test_a_new_base_heard_after_it_moved_counts_its_motion_from_zero() -> None:
    """The new base was matched late: its first sample heard says it drove 0.3 m since it started
    at zero where the old one left the robot; a first reading further than the robot could have
    gone since the last sample is no motion."""
    odometry = ContinuousOdometry()
    odometry.take(_sample((1.0, 0.0, math.pi / 2), 1.0, 5, session=3))
    assert odometry.take(_sample((0.3, 0.0, 0.0), 4.0, 30, session=4)) == pytest.approx((1.0, 0.3, math.pi / 2))
    far = ContinuousOdometry()
    far.take(_sample((1.0, 0.0, math.pi / 2), 1.0, 5, session=3))
    assert far.take(_sample((3.0, 0.0, 0.0), 1.2, 30, session=4)) == pytest.approx((1.0, 0.0, math.pi / 2))
    assert odometry.resets == far.resets == 1


def test_a_jump_no_robot_could_make_is_a_restart_too() -> None:
    """A base whose numbering did not start again (another driver on the same stream) but whose
    odometry jumped 3 m in 0.1 s."""
    odometry = ContinuousOdometry()
    odometry.take(_sample((3.0, 0.0, 0.0), 1.0, 10))
    assert odometry.take(_sample((0.0, 0.0, 0.0), 1.1, 11)) == pytest.approx((3.0, 0.0, 0.0))
    assert odometry.resets == 1
    assert odometry.take(_sample((0.04, 0.0, 0.0), 1.2, 12)) == pytest.approx((3.04, 0.0, 0.0))
    assert odometry.resets == 1


poses = st.tuples(st.floats(-50, 50), st.floats(-50, 50), st.floats(-3.1, 3.1))


@settings(max_examples=60, deadline=None)
@given(before=poses, restart_at=poses, motion=st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(-3, 3)))
def test_motion_after_a_restart_is_the_same_motion_in_the_old_frame(before, restart_at, motion) -> None:
    """Whatever the old and the new process reported, the new process's zero is where the old
    one left the robot (its first reading, 99 s later, is within reach), and the robot's motion
    after the restart is seen unchanged (as seen from the robot) in the consumer's frame."""
    odometry = ContinuousOdometry()
    last = odometry.take(_sample(before, 1.0, 5))
    first = odometry.take(_sample(restart_at, 100.0, 1))
    assert first == pytest.approx(tuple(compose(last, restart_at)), abs=1e-9)
    moved = tuple(compose(restart_at, motion))
    after = odometry.take(_sample(moved, 200.0, 2))
    assert relative(first, after) == pytest.approx(relative(restart_at, moved), abs=1e-6)
