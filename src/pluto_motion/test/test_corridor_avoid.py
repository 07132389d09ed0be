"""The LaserAvoider's choice of a free direction (pluto_motion.corridor_avoid)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings, strategies as st

from avoider_sim import run_avoider
from goto_sim import box
from pluto_motion.corridor_avoid import (ESCAPE_ANGLE, AvoidSettings, choose, free_lengths, scan_to_points,
                                         turn_step)

HALF = 0.5
points_st = st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3)), min_size=1, max_size=30)


def _touching(points: np.ndarray, center: np.ndarray) -> np.ndarray:
    return np.hypot(*(points - center).T) < HALF - 1e-6


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Each point's distance from the segment ``a``-``b``."""
    ab = b - a
    t = np.clip((points - a) @ ab / (ab @ ab), 0.0, 1.0)
    return np.hypot(*(points - (a + t[:, None] * ab)).T)


@settings(max_examples=200, deadline=None)
@example(raw=[(0.0, -0.5)], heading=-1.192092896e-07)    # a rim point met at a grazing angle (a CI-like run)
@given(points_st, st.floats(-math.pi, math.pi))
def test_the_free_length_is_exact_for_a_swept_disc(raw: list, heading: float) -> None:
    points = np.array(raw)
    limit = 2.5
    free = float(free_lengths(points, np.array([heading]), HALF, limit)[0])
    direction = np.array([math.cos(heading), math.sin(heading)])
    already = _touching(points, np.zeros(2))
    nearer = already & (points @ direction > 1e-9)
    if nearer.any():
        assert free == 0.0              # already touching and coming nearer: no move (fail closed)
    start = np.hypot(*points[already].T)
    for s in np.linspace(0.0, max(free - 1e-4, 0.0), 60):
        center = s * direction
        assert not _touching(points[~already], center).any() or free == 0.0
        assert (np.hypot(*(points[already] - center).T) >= start - 1e-9).all()   # only moves away
    if free < limit - 1e-3 and free > 0:
        # Just beyond the free length the disc reaches a point: somewhere on the next millimetre
        # (not necessarily at its end: a point met at a grazing angle, e.g. one on the disc's rim
        # beside a heading that turns 1e-7 rad towards it, is touched over 1e-7 m and left again).
        assert (_segment_distance(points[~already], free * direction, (free + 1e-3) * direction)
                <= HALF + 1e-9).any()


def test_a_robot_come_too_near_turns_away_and_then_moves_away() -> None:
    box = np.array([[0.4, y] for y in np.linspace(-0.3, 0.3, 13)])     # 0.4 m ahead: inside the margin
    goal = (3.0, 0.5)
    choice = choose(box, goal)
    assert choice.rotate and not choice.blocked
    assert choice.heading == pytest.approx(ESCAPE_ANGLE)                # nearly a quarter turn, to the goal's side
    c, s = math.cos(choice.heading), math.sin(choice.heading)
    turned = box @ np.array([[c, -s], [s, c]])                           # the points after the turn
    goal_turned = (goal[0] * c + goal[1] * s, -goal[0] * s + goal[1] * c)
    after = choose(turned, goal_turned)
    assert not after.blocked and not after.rotate and after.length > 0
    direction = np.array([math.cos(after.heading), math.sin(after.heading)])
    gaps = [np.hypot(*(turned - t * direction).T).min() for t in np.linspace(0, after.length, 20)]
    assert all(b >= a - 1e-9 for a, b in zip(gaps, gaps[1:]))            # it only moves away


@settings(max_examples=300, deadline=None)
@given(points_st, st.floats(-math.pi, math.pi))
def test_a_turn_driven_as_a_step_never_brings_the_robot_nearer_a_point_it_could_touch(
        raw: list, turn: float) -> None:
    """A Navigator's stand-in for a turn (:func:`turn_step`): a point outside the grown disc stays
    outside over the whole step, and one inside it is not come nearer to."""
    points = np.array(raw)
    length = 0.1
    heading = turn_step(points, turn, HALF, length)
    if heading is None:
        return
    end = length * np.array([math.cos(heading), math.sin(heading)])
    start = np.hypot(*points.T)
    along = _segment_distance(points, np.zeros(2), end)
    assert (along >= np.minimum(start, HALF) - 1e-6).all()


def test_the_escape_turn_of_a_navigator_steps_beside_the_box_not_into_it() -> None:
    """The case a test saw: a box inside the margin, the escape turn asked of a Navigator.  A step
    along the turn would come 3.4 cm nearer the box each time; the stand-in steps along the free
    heading nearest to the turn, which leaves the box beside or behind it."""
    box = np.array([[0.4, y] for y in np.linspace(-0.3, 0.3, 13)])
    choice = choose(box, (3.0, 0.5))
    assert choice.rotate
    along_turn = 0.1 * np.array([math.cos(choice.heading), math.sin(choice.heading)])
    assert np.hypot(*(box - along_turn).T).min() < np.hypot(*box.T).min() - 0.03
    step = turn_step(box, choice.heading, 0.5, 0.1)
    assert choice.heading < step < math.pi                               # on the goal's side, not back
    end = 0.1 * np.array([math.cos(step), math.sin(step)])
    assert (_segment_distance(box, np.zeros(2), end) >= np.minimum(np.hypot(*box.T), 0.5) - 1e-9).all()
    far = box + [2.0, 0.0]
    assert turn_step(far, 1.2, 0.5, 0.1) == pytest.approx(1.2)           # a free turn goes its way
    ring = np.array([[0.45 * math.cos(a), 0.45 * math.sin(a)] for a in np.linspace(0, math.tau, 90)])
    assert turn_step(ring, choice.heading, 0.5, 0.1) is None             # boxed in: no step


def test_a_wall_ahead_is_steered_round_and_a_box_is_blocked() -> None:
    wall = np.array([[1.2, y] for y in np.linspace(-0.8, 0.8, 33)])
    choice = choose(wall, (3.0, 0.0), AvoidSettings())
    assert not choice.blocked and abs(choice.heading) > math.radians(20)
    free = free_lengths(wall, np.array([choice.heading]), 0.5, choice.length + 1e-3)[0]
    assert free >= choice.length - 1e-9 and choice.length >= AvoidSettings().min_step
    ring = np.array([[0.6 * math.cos(a), 0.6 * math.sin(a)] for a in np.linspace(-math.pi, math.pi, 72)])
    assert choose(ring, (3.0, 0.0)).blocked


def test_goals_behind_are_turned_to_and_near_goals_are_reached() -> None:
    empty = np.zeros((0, 2))
    behind = choose(empty, (-2.0, 0.5))
    assert behind.rotate and abs(behind.heading) > math.radians(160)
    assert choose(empty, (0.1, 0.0)).reached
    straight = choose(empty, (4.0, 0.0))
    assert straight.heading == 0.0 and straight.length == AvoidSettings().lookahead


def test_a_side_once_taken_is_kept_unless_the_other_is_clearly_better() -> None:
    """Two ways round a wall straight ahead, each as near the goal's bearing as the other: the kept
    side wins, and the choice says which side it took."""
    wall = np.array([[1.2, y] for y in np.linspace(-0.6, 0.6, 25)])
    left, right = choose(wall, (3.0, 0.0), side=1), choose(wall, (3.0, 0.0), side=-1)
    assert left.heading > 0 and left.side == 1 and right.heading < 0 and right.side == -1
    # A wall whose right end is just off the bearing (0.35 rad round it), its left 3 m away (0.91
    # rad): the right is taken although the left was kept; 0.42 rad against 0.91 is kept left.
    open_right = np.array([[1.5, y] for y in np.linspace(0.0, 3.0, 121)])
    assert choose(open_right, (3.0, 0.0), side=1).side == -1
    nearly = np.array([[1.5, y] for y in np.linspace(-0.1, 3.0, 125)])
    assert choose(nearly, (3.0, 0.0)).side == -1 and choose(nearly, (3.0, 0.0), side=1).side == 1
    assert choose(np.zeros((0, 2)), (3.0, 0.0), side=1).side == 0        # straight at the goal: none


ROBOT_RADIUS = AvoidSettings().radius
MIDDLE_BOX = box(2.0, -0.3, 2.6, 0.3)


def test_the_guides_pair_goes_round_a_box_straight_between_it_and_the_goal() -> None:
    """Chapter 1's avoider and mover (:mod:`avoider_sim`), the goal 1.4 m beyond the middle of a
    box: before the kept side, the two ways round tied and the robot turned left and right in
    turn, in place, until the run's time ran out."""
    for noise, seed in ((0.0, 0), (0.01, 1), (0.01, 2)):
        run = run_avoider(MIDDLE_BOX, (0.0, 0.0, 0.0), (4.0, 0.0), noise=noise, seed=seed)
        assert run.result == 'reached', f'noise {noise}, seed {seed}: ended at {run.path[-1]}'
        assert run.min_clearance > ROBOT_RADIUS
        assert max(abs(p[1]) for p in run.path) > 0.3 + ROBOT_RADIUS        # round the box


@pytest.mark.parametrize('start', [(1.55, 0.0, 0.0), (1.56, -0.1, 0.25), (1.55, 0.15, -0.2)])
def test_the_guides_pair_gets_out_of_the_margin_of_a_box_with_the_goal_beyond(start) -> None:
    """Started 0.1 m from the box, inside the 0.15 m safety margin (late scans let a robot come so
    near), the goal beyond the box.  Before: a turn driven as a 0.1 m step behind the robot was
    within the mover's "just past it" rule and taken as done (the robot stood), and with that
    fixed, the way out and the turn to the goal at the fan's edge undid each other."""
    run = run_avoider(MIDDLE_BOX, start, (4.0, 0.0), noise=0.01, seed=3)
    assert run.result == 'reached', f'ended at {run.path[-1]}'
    assert run.min_clearance > ROBOT_RADIUS


@pytest.mark.parametrize('far, half, start, goal, seed', [
    (2.74, 0.29, (1.61, -0.16, -0.17), (5.37, 0.12), 7),
    (2.91, 0.17, (1.61, -0.15, 0.24), (5.45, 0.17), 10),
    (3.0, 0.2, (1.6, 0.05, -0.17), (5.5, -0.12), 10),
    (2.61, 0.24, (1.62, 0.12, -0.02), (5.3, 0.29), 8)])
def test_the_guides_pair_keeps_clear_of_a_box_it_no_longer_sees(far, half, start, goal, seed) -> None:
    """Started 0.03-0.05 m from a box's face (``bench/guide_avoider.py``'s margin runs that
    touched): turning away, the laser, ahead of the robot's centre, lost the box while the disc
    was still beside it, and the avoider, looking at the last scan only, drove the disc into the
    corner it had just seen (up to 2.7 cm deep).  The scan memory keeps such points."""
    walls = box(2.0, -half, far, half) + box(-1.0, -3.0, 7.0, 3.0)
    run = run_avoider(walls, start, goal, noise=0.01, seed=seed)
    assert run.result == 'reached', f'ended at {run.path[-1]}'
    assert run.min_clearance > ROBOT_RADIUS, f'came within {run.min_clearance - ROBOT_RADIUS:+.3f} m of the box'


def test_scan_points_drop_invalid_readings_and_apply_the_mount() -> None:
    points = scan_to_points([1.0, -1.0, math.inf, 9.0, 2.0], -math.pi / 2, math.pi / 4, x_offset=0.2,
                            max_range=8.0)
    assert points.shape == (2, 2)
    assert np.allclose(points[0], [0.2, -1.0]) and np.allclose(points[1], [0.2 + 2.0 * math.cos(math.pi / 2), 2.0])


@pytest.mark.parametrize('far, half, start, goal, seed', [
    (2.447, 0.26, (1.501, 0.042, 0.052), (5.223, 0.169), 16),
    (2.645, 0.2425, (1.547, -0.038, -0.058), (5.323, -0.247), 17)])
def test_late_scans_placed_at_their_stamps_keep_the_robot_clear(far, half, start, goal, seed) -> None:
    """A SICK at 9600 baud: a scan every 0.75 s, 0.75 s old when it arrives (``bench/guide_avoider.py``'s
    margin runs).  Taken for scans of where the robot is when it looks, they showed the box where
    it had been relative to the robot before its last turn, and the robot drove into it (5.5 cm
    and 0.9 cm deep, neither reached its goal); placed at the pose of their stamps and moved to where the robot is now
    (:mod:`pluto_nav.pose_history`, as the LaserAvoider does), it keeps clear."""
    walls = box(2.0, -half, far, half) + box(-1.0, -3.0, 7.0, 3.0)
    run = run_avoider(walls, start, goal, noise=0.01, seed=seed, scan_period=0.75, latency=0.75)
    assert run.result == 'reached', f'ended at {run.path[-1]}'
    assert run.min_clearance > ROBOT_RADIUS, f'came within {run.min_clearance - ROBOT_RADIUS:+.3f} m of the box'


#: bench/guide_avoider.py's cluttered room 34 of seed 2 (three boxes) and margin run 18 of seed 2.
CLUTTER_2_34 = (box(2.6691, -0.5729, 3.4691, -0.1272) + box(3.4052, 0.0982, 4.0185, 0.3814)
                + box(2.8414, 0.8154, 3.3793, 1.1728), (0.0, -0.2685, -0.17), (6.0, 0.4912), 34)
MARGIN_2_18 = (box(2.0, -0.3338, 2.7766, 0.3338), (1.619, -0.0113, 0.2723), (5.3883, 0.0476), 18)


@pytest.mark.parametrize('boxes, start, goal, seed', [CLUTTER_2_34, MARGIN_2_18])
def test_a_goal_behind_a_way_round_does_not_hold_the_robot_turning_where_it_stands(boxes, start, goal, seed) -> None:
    """With the SICK at 9600 baud.  Going round a box with the goal behind, the avoider turned to
    the goal once it was 30 degrees beyond the fan and took the way round once it was back within:
    each undid the other before the mover, which turns first, had faced it, and the robot turned
    back and forth where it stood.  After 5 s of that the scan memory forgot the box's corner
    beside it and the robot drove its disc into it (0.7 cm, and 0.03 cm in the margin run).  Now,
    going round, the goal is never turned to (the free heading in view nearest to it is), and a
    memory is forgotten by motion, not time."""
    walls = boxes + box(-1.0, -3.0, 7.0, 3.0)
    run = run_avoider(walls, start, goal, noise=0.01, seed=seed, scan_period=0.75, latency=0.75)
    assert run.result == 'reached', f'ended at {run.path[-1]}'
    assert run.min_clearance > ROBOT_RADIUS, f'came within {run.min_clearance - ROBOT_RADIUS:+.3f} m of a box'
    assert _turns_back_standing(run.path) < 10, 'turned back and forth where it stood'


#: bench/guide_avoider.py's cluttered rooms 2 of seed 2 and 16 of seed 3.
CLUTTER_2_2 = (box(2.2132, 0.4709, 2.6957, 1.2259) + box(1.661, -1.2447, 1.9822, -0.3371)
               + box(3.2461, 0.4359, 3.8328, 0.9611), (0.0, 0.0099, 0.0934), (6.0, 0.7242), 2)
CLUTTER_3_16 = (box(2.9956, -1.2483, 3.2341, -0.7158) + box(3.7412, -0.7886, 4.3427, -0.2643)
                + box(2.103, 0.159, 2.4879, 0.6565), (0.0, 0.1592, -0.0048), (6.0, 0.5678), 16)


@pytest.mark.parametrize('boxes, start, goal, seed', [CLUTTER_2_2, CLUTTER_3_16])
def test_a_robot_turning_weighs_the_same_directions(boxes, start, goal, seed) -> None:
    """With the SICK at 38400 baud.  A narrow way free for the whole look-ahead was on the heading
    grid at one heading and between two of its headings 2 degrees on, when the grid turned with
    the robot: the choice went from it to a way nearer the goal free for part of the look-ahead and
    back, and the robot turned back and forth where it stood until its time ran out.  The grid
    is now fixed in the odometry frame."""
    walls = boxes + box(-1.0, -3.0, 7.0, 3.0)
    run = run_avoider(walls, start, goal, noise=0.01, seed=seed, scan_period=0.2, latency=0.2)
    assert run.result == 'reached', f'ended at {run.path[-1]}'
    assert run.min_clearance > ROBOT_RADIUS, f'came within {run.min_clearance - ROBOT_RADIUS:+.3f} m of a box'
    assert _turns_back_standing(run.path) < 10, 'turned back and forth where it stood'


def _turns_back_standing(path: list) -> int:
    """The most times the robot reversed its turn in one stand (moving less than 1 mm a step)."""
    most, count, last = 0, 0, 0.0
    for a, b in zip(path, path[1:]):
        if math.dist(a[:2], b[:2]) >= 1e-3:
            count, last = 0, 0.0
            continue
        turn = math.remainder(b[2] - a[2], math.tau)
        count += turn * last < 0
        most = max(most, count)
        last = turn if abs(turn) > 1e-6 else last
    return most
