"""Dead reckoning and the Post_Pose adjustment, as pure functions of their inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pluto_nav.adjustment import Adjuster
from pluto_nav.dead_reckoning import DMU_HEARD_S, HISTORY_WALL_S, RESET_SIGMA, DeadReckoning
from pluto_nav.geometry import compose, relative
from pluto_nav.streams import LocPose


def _arc(steps: int, dt: float, tv: float, rv: float, heading_error: float = 0.0):
    """Exact poses along an arc; the odometry's heading gains ``heading_error`` rad per step."""
    x = y = theta = 0.0
    odo_theta = 0.0
    for k in range(steps + 1):
        yield k * dt, (x, y, theta), odo_theta
        x += tv * dt * math.cos(theta + rv * dt / 2)
        y += tv * dt * math.sin(theta + rv * dt / 2)
        theta += rv * dt
        odo_theta += rv * dt + heading_error


def test_rotation_comes_from_the_dmu_when_fresh_and_from_odometry_when_not() -> None:
    with_dmu = DeadReckoning((0.0, 0.0, 0.0))
    without = DeadReckoning((0.0, 0.0, 0.0))
    for t, (x, y, theta), odo_theta in _arc(100, 0.1, 0.5, 0.2, heading_error=0.002):
        # Odometry positions are true but its heading drifts; the DMU's heading is true.
        with_dmu.add_dmu(t, theta, 0.01, -0.02)
        with_dmu.add_odometry(t, x, y, odo_theta)
        without.add_odometry(t, x, y, odo_theta)
    assert with_dmu.dmu_steps == 100 and with_dmu.odometry_steps == 0
    assert without.odometry_steps == 100
    assert with_dmu.latest.pose[2] == pytest.approx(2.0, abs=1e-9)
    assert without.latest.pose[2] == pytest.approx(2.0 + 0.2, abs=1e-9)   # the drift, uncorrected
    assert (with_dmu.latest.phi, with_dmu.latest.psi) == (pytest.approx(0.01), pytest.approx(-0.02))
    assert np.all(np.linalg.eigvalsh(with_dmu.latest.covariance) > 0)
    # Heading from the DMU is surer than from the odometry.
    assert with_dmu.latest.covariance[2, 2] < without.latest.covariance[2, 2]


def test_an_odometry_sample_waits_for_the_dmu_but_not_for_ever() -> None:
    wall = [0.0]
    dr = DeadReckoning((1.0, 2.0, 0.0), dmu_stale_s=0.25, clock=lambda: wall[0])
    dr.add_dmu(0.0, 0.0, 0.0, 0.0)
    assert len(dr.add_odometry(0.0, 0.0, 0.0, 0.0)) == 1
    assert dr.add_odometry(0.1, 0.1, 0.0, 0.0) == []          # the DMU has not reached 0.1 yet
    assert len(dr.add_dmu(0.12, 0.0, 0.0, 0.0)) == 1           # now it has
    assert dr.add_odometry(0.2, 0.2, 0.0, 0.0) == []
    # 0.38 s of odometry ahead of the DMU, but the DMU was heard a moment ago: late, not gone.
    assert dr.add_odometry(0.5, 0.5, 0.0, 0.0) == []
    wall[0] = DMU_HEARD_S + 0.01                               # the DMU went quiet
    done = dr.add_odometry(0.6, 0.6, 0.0, 0.0)
    assert [s.stamp for s in done] == [0.2, 0.5, 0.6] and not done[-1].dmu_used
    assert dr.latest.pose == pytest.approx([1.6, 2.0, 0.0])


def test_without_a_wall_clock_the_dmu_is_waited_for_by_the_stamps_alone() -> None:
    dr = DeadReckoning((1.0, 2.0, 0.0), dmu_stale_s=0.25, clock=None)      # a recording replayed
    dr.add_dmu(0.0, 0.0, 0.0, 0.0)
    assert len(dr.add_odometry(0.0, 0.0, 0.0, 0.0)) == 1
    assert dr.add_odometry(0.2, 0.2, 0.0, 0.0) == []
    done = dr.add_odometry(0.5, 0.5, 0.0, 0.0)                  # 0.38 s > 0.25 s: absent
    assert [s.stamp for s in done] == [0.2, 0.5] and not done[-1].dmu_used


def test_a_dmu_behind_a_backlog_of_odometry_still_gives_every_turn() -> None:
    """The soak's case: just after a base restart the DMU process fell 0.3 s behind the odometry
    while the robot turned at 1 rad/s; its samples came late, and the turn must be theirs."""
    wall = [0.0]
    dr = DeadReckoning((0.0, 0.0, 0.0), dmu_stale_s=0.25, clock=lambda: wall[0])
    dr.add_dmu(0.0, 0.0, 0.0, 0.0)
    dr.add_odometry(0.0, 0.0, 0.0, 0.0)
    done = []
    for k in range(1, 6):                          # the odometry's turn is 20 % too much
        done += dr.add_odometry(0.1 * k, 0.0, 0.0, 0.12 * k)
    assert done == []                              # 0.5 s ahead of a DMU heard a moment ago
    wall[0] = 0.4
    for k in range(1, 27):                         # the DMU's late samples, 50 Hz, the true turn
        done += dr.add_dmu(0.02 * k, 0.1 * 0.2 * k, 0.0, 0.0)
    assert [s.stamp for s in done] == pytest.approx([0.1, 0.2, 0.3, 0.4, 0.5])
    assert all(s.dmu_used for s in done)
    assert dr.latest.pose[2] == pytest.approx(0.5, abs=1e-9)


@settings(max_examples=50, deadline=None)
@given(t=st.floats(6.0, 10.0))
def test_interpolation_stays_between_the_samples_of_the_history(t: float) -> None:
    wall = [0.0]
    dr = DeadReckoning((0.0, 0.0, 0.0), clock=lambda: wall[0])
    for stamp, (x, y, theta), _ in _arc(100, 0.1, 0.4, 0.3):
        wall[0] = stamp                              # odometry as it comes, in real time
        dr.add_odometry(stamp, x, y, theta)
    sample = dr.at(t)
    assert sample is not None
    a = max((s for s in dr.history if s.stamp <= t), key=lambda s: s.stamp)
    b = min((s for s in dr.history if s.stamp >= t), key=lambda s: s.stamp)
    for axis in (0, 1):
        assert min(a.pose[axis], b.pose[axis]) - 1e-9 <= sample.pose[axis] <= max(a.pose[axis], b.pose[axis]) + 1e-9
    assert dr.at(10.5) is None                       # after the latest sample
    assert dr.at(1.0) is None                        # older than the history keeps


def test_a_laser_post_pose_adjusts_the_pose_not_the_dead_reckoning() -> None:
    dr = DeadReckoning((0.0, 0.0, 0.0))
    for stamp, (x, y, theta), _ in _arc(20, 0.1, 0.5, 0.0):
        dr.add_odometry(stamp, x, y, theta)
    adjuster = Adjuster(mount=(0.2, 0.0))
    # The estimator says: at t = 1.0 the laser was at (1.7, 0.1, 0.05) (dead reckoning: (0.7, 0, 0)).
    post = LocPose(pose=(1.7, 0.1, 0.0, 0.05, 0.0, 0.0), setter=1, stamp=1.0,
                   covariance=np.diag([1e-4, 1e-4, 1e-5]))
    assert adjuster.write(post, 'poseModule', dr) is None
    at_one = dr.at(1.0)
    robot_then = adjuster.pose(at_one)
    assert adjuster.laser(robot_then) == pytest.approx([1.7, 0.1, 0.05], abs=1e-9)
    # Now (t = 2.0) the robot drove 0.5 m more along its own heading.
    now = adjuster.pose(dr.latest)
    assert relative(robot_then, now) == pytest.approx([0.5, 0.0, 0.0], abs=1e-9)
    assert dr.latest.pose == pytest.approx([1.0, 0.0, 0.0])
    assert adjuster.setter == 1 and adjuster.holder == 'poseModule'


def test_the_setter_rules() -> None:
    dr = DeadReckoning((0.0, 0.0, 0.0))
    dr.add_odometry(0.0, 0.0, 0.0, 0.0)
    adjuster = Adjuster()
    pose = (1.0, 1.0, 0.0, 0.0, 0.0, 0.0)
    assert adjuster.write(LocPose(pose=pose, setter=-1), 'user', dr) is None      # free: a user sets
    assert adjuster.write(LocPose(pose=pose, setter=1), 'poseModule', dr) is None  # an estimator takes over
    assert adjuster.write(LocPose(pose=pose, setter=-1), 'user', dr).reason.startswith('setter 1')
    assert adjuster.write(LocPose(pose=pose, setter=2), 'slamModule', dr) is not None
    assert adjuster.write(LocPose(pose=pose, setter=0), 'slamModule', dr) is not None
    assert adjuster.write(LocPose(pose=(math.nan,) + pose[1:], setter=1), 'poseModule', dr).reason == 'not finite'
    assert adjuster.write(LocPose(pose=pose, setter=0), 'poseModule', dr) is None   # released
    assert adjuster.write(LocPose(pose=pose, setter=2), 'slamModule', dr) is None
    assert adjuster.write(LocPose(pose=pose, setter=3), 'slamModule', dr) is None   # saving
    assert adjuster.write(LocPose(pose=pose, setter=2), 'slamModule', dr) is None
    assert len(adjuster.refusals) == 4 and adjuster.setter == 2
    # A robot pose sets the robot itself (no mounting applied).
    adjuster = Adjuster(mount=(0.2, 0.0))
    adjuster.write(LocPose(pose=(3.0, 4.0, 0.0, 1.0, 0.0, 0.0), setter=-1), 'user', dr)
    assert adjuster.pose(dr.latest) == pytest.approx(compose([3.0, 4.0, 1.0], [0.0, 0.0, 0.0]))


def test_odometry_that_starts_again_from_zero_is_no_motion() -> None:
    """A restarted base counts from zero again: dead reckoning must not jump back with it."""
    dr = DeadReckoning((2.0, 3.0, 0.5))
    for k in range(41):
        dr.add_odometry(0.1 * k, 0.05 * k, 0.0, 0.0)       # 0.5 m/s straight on for 2 m
    before = dr.latest.pose.copy()
    dr.add_odometry(4.1, 0.0, 0.0, 0.0)                     # the base restarted
    assert dr.odometry_resets == 1
    assert dr.latest.pose == pytest.approx(before)
    dr.add_odometry(4.2, 0.05, 0.0, 0.0)                    # and drives on from its new zero
    assert relative(before, dr.latest.pose) == pytest.approx([0.05, 0.0, 0.0])


def test_a_base_down_long_enough_to_hide_its_jump_is_still_no_motion() -> None:
    """Down for 10 s, the restarted base's jump back of 2 m is slower than any speed limit: only
    its first sample's flag (the base numbers its messages from 1 again) tells."""
    dr = DeadReckoning((2.0, 3.0, 0.5))
    for k in range(41):
        dr.add_odometry(0.1 * k, 0.05 * k, 0.0, 0.0)
    before = dr.latest.pose.copy()
    dr.add_odometry(14.0, 0.0, 0.0, 0.0)                    # unflagged: 0.2 m/s, taken as motion
    assert dr.odometry_resets == 0 and relative(before, dr.latest.pose)[0] == pytest.approx(-2.0)
    dr = DeadReckoning((2.0, 3.0, 0.5))
    for k in range(41):
        dr.add_odometry(0.1 * k, 0.05 * k, 0.0, 0.0)
    dr.add_odometry(14.0, 0.0, 0.0, 0.0, restarted=True)
    assert dr.odometry_resets == 1 and dr.latest.pose == pytest.approx(before)
    dr.add_odometry(14.1, 0.05, 0.0, 0.0)
    assert relative(before, dr.latest.pose) == pytest.approx([0.05, 0.0, 0.0])


def test_a_restarted_dmu_integrating_from_zero_again_turns_nothing() -> None:
    """The DMU's heading is integrated since its process started: a new process's heading of 0
    after 1 rad is no turn of the robot, and the turns after it count from there."""
    dr = DeadReckoning((0.0, 0.0, 0.0))
    for k in range(11):                                     # 1 rad in 1 s, the DMU agreeing
        dr.add_dmu(0.1 * k, 0.1 * k, 0.0, 0.0)
        dr.add_odometry(0.1 * k, 0.0, 0.0, 0.1 * k)
    assert dr.latest.pose[2] == pytest.approx(1.0)
    dr.add_dmu(5.0, 0.0, 0.0, 0.0, restarted=True)          # down 4 s, standing still
    dr.add_odometry(5.0, 0.0, 0.0, 1.0)
    dr.add_dmu(5.1, 0.1, 0.0, 0.0)
    dr.add_odometry(5.1, 0.0, 0.0, 1.1)
    assert dr.latest.pose[2] == pytest.approx(1.1)
    assert dr.latest.dmu_used


def test_a_resumed_dead_reckoning_whose_base_restarted_meanwhile_takes_no_motion() -> None:
    """The localModule resumed at a reading of the old base; the first sample is the new base's
    (flagged: numbered lower than the saved one), 12 m back in 3 s: no motion, not 4 m/s."""
    dr = DeadReckoning((10.0, 5.0, 0.0), resume_odometry=(100.0, (12.0, 0.0, 0.0)))
    dr.add_odometry(103.0, 0.0, 0.0, 0.0, restarted=True)
    assert dr.latest.pose == pytest.approx([10.0, 5.0, 0.0]) and dr.odometry_resets == 1
    dr = DeadReckoning((10.0, 5.0, 0.0), resume_odometry=(100.0, (12.0, 0.0, 0.0)))
    dr.add_odometry(103.0, 0.0, 0.0, 0.0)
    assert dr.latest.pose[0] == pytest.approx(-2.0)


def test_a_reset_step_is_as_uncertain_as_the_motion_it_may_hide() -> None:
    """The motion lost with a restarted base is not known to be none: the reset step's covariance
    holds RESET_SIGMA (the heading's only when no DMU measured the turn), and so does the
    increment a scan spanning it gets; the steps around it keep odometry's small ones."""
    dr = DeadReckoning((2.0, 3.0, 0.5))
    for k in range(41):
        dr.add_odometry(0.1 * k, 0.05 * k, 0.0, 0.0)
    dr.add_odometry(4.1, 0.0, 0.0, 0.0, restarted=True)
    reset = dr.latest
    variances = np.diag(reset.increment_cov)
    assert np.all(variances >= np.square(RESET_SIGMA)) and np.all(variances < 1.01 * np.square(RESET_SIGMA))
    dr.add_odometry(4.2, 0.05, 0.0, 0.0)
    assert np.all(np.sqrt(np.diag(dr.latest.increment_cov)) < 0.05)
    _, spanning = dr.increment_between(4.05, 4.15)
    assert np.sqrt(spanning[0, 0]) == pytest.approx(RESET_SIGMA[0], rel=0.02)
    _, after = dr.increment_between(4.15, 4.2)
    assert np.sqrt(after[0, 0]) < 0.05

    with_dmu = DeadReckoning((0.0, 0.0, 0.0))
    for k in range(11):
        with_dmu.add_dmu(0.1 * k, 0.0, 0.0, 0.0)
        with_dmu.add_odometry(0.1 * k, 0.05 * k, 0.0, 0.0)
    with_dmu.add_dmu(1.1, 0.0, 0.0, 0.0)
    with_dmu.add_odometry(1.1, 0.0, 0.0, 0.0, restarted=True)
    q = with_dmu.latest.increment_cov
    assert with_dmu.latest.dmu_used and q[0, 0] >= RESET_SIGMA[0] ** 2 and q[2, 2] < 1e-4


def test_within_a_gap_of_the_odometry_the_heading_is_the_dmus() -> None:
    """The base was down 4 s: the robot stood 3 s, then turned 1 rad in the last second (the DMU
    sampled on at 50 Hz).  A scan placed inside the gap takes the DMU's heading at its time, not
    a heading drawn straight across the gap (0.75 rad at 3 s in); and an increment between two
    scans inside the gap carries its share of the reset step's RESET_SIGMA, not the tiny motion
    of a straight line."""
    dr = DeadReckoning((0.0, 0.0, 0.0))
    for k in range(11):
        dr.add_dmu(0.1 * k, 0.0, 0.0, 0.0)
        dr.add_odometry(0.1 * k, 0.0, 0.0, 0.0)
    for k in range(1, 201):                                 # 1.0 s to 5.0 s
        t = 1.0 + 0.02 * k
        dr.add_dmu(t, max(0.0, t - 4.0), 0.0, 0.0)
    dr.add_odometry(5.0, 0.0, 0.0, 0.0, restarted=True)
    assert dr.latest.dmu_used and dr.latest.pose[2] == pytest.approx(1.0)
    assert dr.at(3.5).pose[2] == pytest.approx(0.0, abs=1e-9)
    assert dr.at(4.0).pose[2] == pytest.approx(0.0, abs=1e-9)
    assert dr.at(4.5).pose[2] == pytest.approx(0.5)
    _, inside = dr.increment_between(2.0, 2.2)
    assert np.sqrt(inside[0, 0]) == pytest.approx(RESET_SIGMA[0] * math.sqrt(0.2 / 4.0), rel=0.05)
    # Without the DMU the straight line is all there is.
    alone = DeadReckoning((0.0, 0.0, 0.0))
    alone.add_odometry(0.0, 0.0, 0.0, 0.0)
    alone.add_odometry(1.0, 0.0, 0.0, 0.0)
    alone.add_odometry(2.0, 0.0, 0.0, 1.0)
    assert alone.at(1.5).pose[2] == pytest.approx(0.5)


def test_a_new_base_heard_after_it_moved_counts_its_motion_from_zero() -> None:
    """The new base process was heard 2 s after it started at zero where the old one left the
    robot, having driven 0.3 m: that is the motion (not none); a first reading further than the
    robot could have gone since the last sample is no motion."""
    dr = DeadReckoning((2.0, 3.0, math.pi / 2))
    for k in range(11):
        dr.add_odometry(0.1 * k, 0.05 * k, 0.0, 0.0)
    before = dr.latest.pose.copy()
    dr.add_odometry(4.0, 0.3, 0.0, 0.0, restarted=True)
    assert dr.odometry_resets == 1 and relative(before, dr.latest.pose) == pytest.approx([0.3, 0.0, 0.0])
    dr.add_odometry(4.1, 0.35, 0.0, 0.0)
    assert relative(before, dr.latest.pose) == pytest.approx([0.35, 0.0, 0.0])
    far = DeadReckoning((2.0, 3.0, math.pi / 2))
    far.add_odometry(0.0, 0.0, 0.0, 0.0)
    far.add_odometry(0.1, 3.0, 0.0, 0.0, restarted=True)       # 3 m in 0.1 s
    assert far.odometry_resets == 1 and far.latest.pose == pytest.approx([2.0, 3.0, math.pi / 2])


def test_a_backlog_worked_through_at_once_keeps_its_history_for_late_scans() -> None:
    """12 s of odometry taken in one step of a loaded machine: a scan timed at its start, whose
    timing message comes a step later, still finds the history; once the wall clock has moved on
    HISTORY_WALL_S, the odometry's own HISTORY_S trims it."""
    wall = [100.0]
    dr = DeadReckoning((0.0, 0.0, 0.0), clock=lambda: wall[0])
    for k in range(121):
        dr.add_odometry(0.1 * k, 0.01 * k, 0.0, 0.0)
    assert dr.at(0.25).pose == pytest.approx([0.025, 0.0, 0.0])
    wall[0] += HISTORY_WALL_S + 0.1
    dr.add_odometry(12.1, 0.121, 0.0, 0.0)
    assert dr.at(0.25) is None and dr.at(7.25).pose == pytest.approx([0.725, 0.0, 0.0])
