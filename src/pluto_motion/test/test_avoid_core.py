"""The avoidModule's pure core without processes: command parsing and refusal, the laser guard and
watch, the vector summation (offline runs in a small kinematic simulation: round a box, stuck
behind a wall, the goal strength), the wall follower and the controller's status."""

from __future__ import annotations

import math

import numpy as np
import pytest
from goto_sim import LASER, box, clearance, raycast, run_goto
from hypothesis import given, settings
from hypothesis import strategies as st

from pluto_motion.avoid_command import CommandRefused, Kind, parse_command
from pluto_motion.avoid_control import GOTO_NORMAL, GOTO_REACHED, THREAD_STOPPED, AvoidController
from pluto_motion.goto_field import FieldSettings, goto_step, nearest_per_bin
from pluto_motion.laser_guard import LASER_FATAL, LASER_SLOW, LaserGuard, LaserWatch, free_distance
from pluto_motion.wall_follow import CAMERA, fit_left_wall, wall_follow_step

ROOM = box(0, 0, 10, 6)


# -- commands ------------------------------------------------------------------------------------
@pytest.mark.parametrize(('flags', 'velocity', 'position', 'force', 'why'), [
    (4, [0.1, 0.0], [], [], 'cmdFlags 4'),
    (42, [0.1, 0.0], [], [], 'cmdFlags 42'),
    (-2, [], [], [], 'cmdFlags -2'),
    (0, [math.nan, 0.0], [], [], 'not finite'),
    (32, [0.5, 1.0], [math.inf, 1.0], [], 'not finite'),
    (32, [0.5, 1.0], [1.0, 1.0], [math.nan], 'not finite'),
    (2, [0.0, 1.0], [1.0, 1.0], [], 'limits must be > 0'),
    (2, [0.5, 1.0], [1.0, 1.0], [-1.0], 'must be > 0'),
    (11, [0.2], [1.0], [], 'position needs 2'),
    (3, [-0.1], [], [], 'speed >= 0'),
])
def test_bad_commands_are_refused_with_the_reason(flags: int, velocity: list[float], position: list[float],
                                                  force: list[float], why: str) -> None:
    with pytest.raises(CommandRefused, match=why):
        parse_command(flags, velocity, position, force)


@given(st.integers(min_value=0, max_value=3), st.integers(min_value=0, max_value=3))
def test_every_flag_of_the_seed_parses_back_to_itself(a: int, t: int) -> None:
    command = parse_command(10 * a + t, [0.4, 0.8], [1.0, 2.0], [1.0])
    assert command is not None and command.cmd_flags == 10 * a + t
    assert command.kind is Kind(t) and command.sonar == bool(a & 1) and command.laser == bool(a & 2)


def test_release_and_goto_defaults() -> None:
    assert parse_command(-1, [], []) is None
    goto = parse_command(32, [0.5, 1.0], [3.0, 4.0])
    assert goto is not None and goto.goal == (3.0, 4.0) and goto.strength == 1.0


# -- laser guard and watch -----------------------------------------------------------------------
@settings(max_examples=200, deadline=None)
@given(st.floats(min_value=0.0, max_value=3.0), st.floats(min_value=-0.39, max_value=0.39),
       st.floats(min_value=0.05, max_value=1.0))
def test_guard_never_allows_more_and_stops_near(x: float, y: float, tv: float) -> None:
    guard = LaserGuard()
    points = np.array([[0.35 + x, y]])
    limited, code = guard.limit(tv, points)
    assert 0.0 <= limited <= tv
    gap = free_distance(points, 0.35, 0.05)
    if gap <= guard.limits.stop:
        assert limited == 0.0 and code == LASER_SLOW
    if gap >= guard.limits.slow:
        assert (limited, code) == (tv, 0)


def test_guard_ignores_the_sides_and_backward_motion() -> None:
    guard = LaserGuard()
    side = np.array([[0.5, 0.6], [0.0, -0.5]])        # beside the corridor
    assert guard.limit(0.5, side) == (0.5, 0)
    ahead = np.array([[0.45, 0.0]])
    assert guard.limit(-0.3, ahead) == (-0.3, 0)
    assert guard.limit(0.3, ahead) == (0.0, LASER_SLOW)


def test_guard_caps_from_the_speed_asked_for_not_a_speed_already_slowed() -> None:
    guard = LaserGuard()
    wall = np.array([[0.35 + 0.6, 0.0]])                 # 0.6 m ahead of the footprint: about half speed
    assert guard.limit(0.04, wall) == (0.0, LASER_SLOW)  # slowed twice: under the creep speed, a stop
    assert guard.limit(0.04, wall, wanted=0.6) == (0.04, 0)   # a goto's slow speed is left alone
    tv, code = guard.limit(0.6, wall, wanted=0.6)
    assert code == LASER_SLOW and 0.2 < tv < 0.4


def test_watch_fatal_and_stale_from_the_period() -> None:
    watch = LaserWatch()
    assert watch.failure(0.0) == 'no scan yet'
    for i in range(5):
        watch.scan([2.0] * 361, stamp=0.2 * i, now=10.0 + 0.2 * i)
    assert watch.period == pytest.approx(0.2) and watch.failure(10.9) is None
    assert watch.stale_after == pytest.approx(0.6)
    assert 'no scan for' in watch.failure(11.5)
    watch.scan([-1.0] * 361, stamp=1.0, now=11.6)
    assert 'fatal' in watch.failure(11.6)


# -- vector summation ----------------------------------------------------------------------------
def test_bins_keep_the_nearest_point_whatever_the_resolution() -> None:
    wall = np.column_stack((np.full(361, 1.0), np.linspace(-1.0, 1.0, 361)))
    dense = nearest_per_bin(wall, 72, 3.0)
    sparse = nearest_per_bin(wall[::20], 72, 3.0)
    assert np.nanmin(dense) == pytest.approx(1.0, abs=1e-3)
    assert np.isfinite(dense).sum() >= np.isfinite(sparse).sum()
    # a sonar echo fills its cone's bins
    cone = nearest_per_bin(np.array([[2.0, 0.0]]), 72, 3.0, np.array([0.22]))
    assert np.isfinite(cone).sum() == 2 * math.ceil(0.22 / (2 * math.pi / 72)) + 1


def test_open_goal_goes_straight_at_full_speed() -> None:
    step = goto_step((0.0, 0.0, 0.0), (5.0, 0.0), np.zeros((0, 2)), max_tv=0.5, max_rv=1.0)
    assert step.heading == pytest.approx(0.0) and step.speed == pytest.approx(0.5) and not step.reached
    assert goto_step((0.0, 0.0, 0.0), (0.1, 0.0), np.zeros((0, 2)), max_tv=0.5, max_rv=1.0).reached


def test_heading_lead_is_limited_by_the_maximum_angular_velocity() -> None:
    step = goto_step((0.0, 0.0, 0.0), (0.0, 5.0), np.zeros((0, 2)), max_tv=0.5, max_rv=0.3)
    assert step.heading == pytest.approx(0.3 / FieldSettings().heading_gain)
    assert step.speed == pytest.approx(0.0, abs=1e-9)        # 90 degrees to turn: turn first


@pytest.mark.parametrize('offset', [0.0, 0.3, -0.3])
def test_goto_steers_round_a_box_without_touching_it(offset: float) -> None:
    walls = ROOM + box(4.5, 2.5 + offset, 5.5, 3.5 + offset)
    run = run_goto(walls, (1.5, 3.0, 0.0), (8.5, 3.0))
    assert run.result == 'reached', run.path[-1]
    assert run.min_clearance > 0.35 + 0.03


@pytest.mark.parametrize('seed', range(12))
def test_goto_round_a_box_holds_its_side_with_late_scans_and_an_uneven_loop(seed: int) -> None:
    # A loaded computer (make test's fresh-clone run of test_avoid_i_goto_typed_at_its_prompt, the
    # same room): scans 0.2-0.8 s old and steps of 0.05-0.35 s turned the lean of the repulsion
    # half way round the box; the goto chose the other side, turned back, circled and was stuck.
    walls = ROOM + box(4.5, 2.5, 5.5, 3.5)
    run = run_goto(walls, (1.5, 3.0, 0.0), (8.5, 3.0), scan_age=(0.2, 0.8), period=(0.05, 0.35), seed=seed)
    assert run.result == 'reached', (run.result, run.path[-1])
    assert run.min_clearance > 0.35


def test_goto_behind_a_wall_is_stuck_without_touching_it() -> None:
    walls = box(0, 0, 6, 4) + [(3.5, 0.0, 3.5, 4.0)]
    run = run_goto(walls, (1.5, 2.0, 0.0), (5.0, 2.0))
    assert run.result == 'stuck' and run.min_clearance > 0.35


@pytest.mark.parametrize('start', [(1.5, 2.0, 0.0), (2.0, 0.8, 0.5), (2.5, 3.4, -0.6)])
@pytest.mark.parametrize('clear', [0.6, 0.7])
def test_a_goal_near_a_wall_is_reached_head_on(start: tuple[float, float, float], clear: float) -> None:
    """The benchmark's goals are 0.6 m or more from walls: a wall beyond the goal must not hold the
    robot short of it (it did, 0.4-0.56 m short, on a generated map: the wall's push against the
    goal balanced the goal's pull there, a potential field's trap)."""
    walls = box(0, 0, 6, 4) + box(5.0, 1.2, 5.8, 2.8)
    goal = (5.0 - clear, 2.0)
    run = run_goto(walls, start, goal)
    assert run.result == 'reached', run.path[-1]
    assert run.min_clearance > 0.35 + 0.03


def test_goal_strength_above_one_lets_the_robot_closer() -> None:
    walls = box(0, 0, 6, 4) + [(3.5, 0.0, 3.5, 4.0)]
    weak = run_goto(walls, (1.5, 2.0, 0.0), (5.0, 2.0), strength=0.7)
    strong = run_goto(walls, (1.5, 2.0, 0.0), (5.0, 2.0), strength=2.0)
    assert strong.path[-1][0] > weak.path[-1][0]


# -- wall follow ---------------------------------------------------------------------------------
def _scan_at(walls: list, x: float, y: float, theta: float) -> np.ndarray:
    ranges = raycast(walls, x + 0.2 * math.cos(theta), y + 0.2 * math.sin(theta), theta + LASER.theta)
    return LASER.points(ranges)


def test_wall_fit_sees_the_left_wall_and_the_camera_distance() -> None:
    walls = [(-5.0, 2.0, 20.0, 2.0)]                       # a wall 2 m to the left, parallel
    angle, distance = fit_left_wall(_scan_at(walls, 0.0, 0.0, 0.0))
    assert angle == pytest.approx(0.0, abs=0.01) and distance == pytest.approx(2.0 - CAMERA[1], abs=0.02)


def test_wall_follow_settles_at_the_distance() -> None:
    walls = [(-5.0, 2.0, 60.0, 2.0)]
    x, y, theta, dt = 0.0, 0.0, 0.0, 0.1
    for _ in range(400):
        tv, rv = wall_follow_step(_scan_at(walls, x, y, theta), 0.3, 0.8)
        x, y, theta = x + tv * dt * math.cos(theta), y + tv * dt * math.sin(theta), theta + rv * dt
    camera_y = y + CAMERA[0] * math.sin(theta) + CAMERA[1] * math.cos(theta)
    assert 2.0 - camera_y == pytest.approx(0.8, abs=0.05) and abs(theta) < 0.05 and x > 5.0


def test_wall_follow_turns_right_at_an_inside_corner() -> None:
    walls = [(-5.0, 1.5, 0.8, 1.5), (0.8, 1.5, 0.8, -5.0)]        # 0.4 m of free distance ahead
    tv, rv = wall_follow_step(_scan_at(walls, 0.0, 0.0, 0.0), 0.3)
    assert tv == 0.0 and rv < 0.0


# -- the controller ------------------------------------------------------------------------------
def test_controller_goto_reaches_and_holds_and_release_stops_once() -> None:
    control = AvoidController()
    control.accept(parse_command(2, [0.5, 1.0], [1.0, 0.0]), now=0.0)
    order = control.step(0.05, (0.0, 0.0, 0.0))
    assert order is not None and order.cmd_flags == 1 and order.velocity[0] > 0
    assert control.status([0.1, 0.0], [0], 0)[1] == [0, GOTO_NORMAL, 0]
    order = control.step(0.1, (0.95, 0.0, 0.0))
    assert order.velocity == (0.0, 0.0)
    assert control.status([0.0, 0.0], [0], 3)[1] == [0, GOTO_REACHED, 3]
    control.set_running(False)
    assert control.step(0.2, (0.95, 0.0, 0.0)).velocity == (0.0, 0.0)
    assert control.step(0.3, (0.95, 0.0, 0.0)) is None
    assert control.status([0.0, 0.0], [0], 3)[1][1] == THREAD_STOPPED


def test_controller_laser_dead_stops_with_seven_and_slow_is_six() -> None:
    control = AvoidController()
    control.accept(parse_command(20, [0.4, 0.0], []), now=0.0)
    order = control.step(0.05, (0.0, 0.0, 0.0))
    assert order.velocity == (0.0, 0.0) and control.status([0.4, 0.0], [0], 0) == ([0.0, 0.0], [LASER_FATAL, 0, 0])
    ranges = [math.inf] * 361
    ranges[180] = 0.35 + 0.5 - 0.2                      # an obstacle 0.5 m ahead of the footprint
    control.set_laser(ranges, LASER.points(ranges), stamp=0.0, now=0.1, pose=None)
    order = control.step(0.15, (0.0, 0.0, 0.0))
    data, element = control.status([0.4, 0.0], [0], 0)
    assert element[0] == LASER_SLOW and 0.0 < order.velocity[0] < 0.4 and data[0] == order.velocity[0]


def test_points_move_with_the_robot_between_scans() -> None:
    control = AvoidController()
    control.accept(parse_command(20, [0.4, 0.0], []), now=0.0)
    ranges = [math.inf] * 361
    ranges[180] = 1.7                                       # 1.9 m from the centre, 1.55 from the edge
    control.set_laser(ranges, LASER.points(ranges), stamp=0.0, now=0.0, pose=(0.0, 0.0, 0.0))
    control.step(0.01, (0.0, 0.0, 0.0))
    assert control.laser_code == 0
    control.step(0.02, (1.0, 0.0, 0.0))                    # 1 m on: 0.55 m left, slowing
    assert control.laser_code == LASER_SLOW


def test_clearance_helper() -> None:
    assert clearance(ROOM, 1.0, 3.0) == pytest.approx(1.0)
