"""A person's walk (wurde_drivers.sim.walk): the position as a pure function of the stamp — legs,
pauses, loops and back-and-forth, the cycle anchored at the epoch, and never faster than its speed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wurde_drivers.sim.walk import BACK_AND_FORTH, LOOP, MAX_SPEED, Walk

#: A stamp of today's order (s since the epoch): the walk must hold there, not only near 0.
NOW = 1_765_000_000.0


def test_a_loop_walks_each_leg_at_its_speed_and_pauses_at_each_point() -> None:
    # A 3 x 4 m right triangle, 1 m/s, 2 s at each corner: 2 + 3, 2 + 5 (the hypotenuse), 2 + 4 s.
    walk = Walk(((0, 0), (3, 0), (3, 4)), speed=1.0, pause=2.0, mode=LOOP)
    assert walk.cycle == pytest.approx(18.0)
    expected = {
        0.0: (0, 0, 0.0), 1.9: (0, 0, 0.0),                 # standing at the first point
        2.0: (0, 0, 0.0), 3.5: (1.5, 0, 0.0),               # leaves it at 2 s
        5.0: (3, 0, math.pi / 2), 6.9: (3, 0, math.pi / 2),  # at the second: facing the next leg
        9.0: (3, 2, math.pi / 2), 11.0: (3, 4, math.atan2(-4, -3)),
        15.5: (1.5, 2, math.atan2(-4, -3)),                 # half way down the hypotenuse
        17.99: (0.006, 0.008, math.atan2(-4, -3)), 18.0: (0, 0, 0.0),
    }
    for t, pose in expected.items():
        assert walk.pose_at(t) == pytest.approx(pose, abs=1e-9), t
        assert walk.pose_at(t + 5 * walk.cycle) == pytest.approx(pose, abs=1e-9), t  # it repeats
        assert walk.pose_at(t - walk.cycle) == pytest.approx(pose, abs=1e-9), t      # and did before


def test_back_and_forth_comes_back_the_same_way_reversed() -> None:
    walk = Walk(((0, 0), (2, 0), (2, 1)), speed=0.5, pause=1.0, mode=BACK_AND_FORTH)
    # Legs: (0,0)-(2,0), (2,0)-(2,1), (2,1)-(2,0), (2,0)-(0,0): 4 + 2 + 2 + 4 s, and 4 pauses.
    assert walk.cycle == pytest.approx(16.0)
    assert [leg for leg in walk.legs] == [((0, 0), (2, 0)), ((2, 0), (2, 1)), ((2, 1), (2, 0)),
                                           ((2, 0), (0, 0))]
    assert walk.pose_at(8.0) == pytest.approx((2.0, 1.0, -math.pi / 2))   # at the far end, turned back
    assert walk.pose_at(14.0) == pytest.approx((1.0, 0.0, math.pi))        # half way home
    # Two points: there and back, the same in both modes.
    pair = [Walk(((1, 1), (4, 5)), 1.0, 0.5, mode) for mode in (LOOP, BACK_AND_FORTH)]
    stamps = NOW + np.linspace(0, 30, 301)
    assert np.allclose(pair[0].poses_at(stamps), pair[1].poses_at(stamps))


def test_the_position_depends_on_the_stamp_alone() -> None:
    """Two processes with clocks started apart agree: the cycle is anchored at stamp 0."""
    walk = Walk(((0, 0), (5, 0)), speed=1.25, pause=0.7)
    phase = NOW % walk.cycle
    assert walk.pose_at(NOW) == pytest.approx(walk.pose_at(phase), abs=1e-6)
    assert Walk(((0, 0), (5, 0)), speed=1.25, pause=0.7).pose_at(NOW + 0.123) == walk.pose_at(NOW + 0.123)
    assert walk.poses_at([NOW, NOW + 1.0]).tolist() == [list(walk.pose_at(NOW)), list(walk.pose_at(NOW + 1.0))]


@pytest.mark.parametrize('points, speed, pause, mode, reason', [
    (((0, 0),), 1.0, 0.0, LOOP, 'at least 2 points'),
    (((0, 0), (1, 0)), 0.0, 0.0, LOOP, 'not in (0, 1.5]'),
    (((0, 0), (1, 0)), 1.51, 0.0, LOOP, 'not in (0, 1.5]'),
    (((0, 0), (1, 0)), math.nan, 0.0, LOOP, 'not in (0, 1.5]'),
    (((0, 0), (1, 0)), 1.0, -1.0, LOOP, 'pause'),
    (((0, 0), (1, 0)), 1.0, 0.0, 'zigzag', 'mode'),
    (((0, 0), (1, math.inf)), 1.0, 0.0, LOOP, 'finite'),
    (((0, 0), (1, 0), (1, 0)), 1.0, 0.0, LOOP, 'points 2 and 3 are the same place'),
    (((0, 0), (1, 0), (0, 0)), 1.0, 0.0, LOOP, 'a loop closes by itself'),
])
def test_a_walk_that_cannot_be_walked_is_refused(points: tuple, speed: float, pause: float, mode: str,
                                                 reason: str) -> None:
    with pytest.raises(ValueError) as error:
        Walk(points, speed, pause, mode)
    assert reason in str(error.value)


waypoints = st.lists(st.tuples(st.floats(-20, 20), st.floats(-20, 20)), min_size=2, max_size=6)


@settings(max_examples=200, deadline=None)
@given(points=waypoints, speed=st.floats(0.05, MAX_SPEED), pause=st.floats(0.0, 5.0),
       mode=st.sampled_from([LOOP, BACK_AND_FORTH]), t0=st.floats(0.0, 2e9), dt=st.floats(0.001, 3.0))
def test_a_person_is_never_faster_than_its_speed_and_always_on_its_path(
        points: list[tuple[float, float]], speed: float, pause: float, mode: str, t0: float, dt: float) -> None:
    try:
        walk = Walk(tuple(points), speed, pause, mode)
    except ValueError:
        return                                       # a repeated point: refused, tested above
    a, b = walk.poses_at([t0, t0 + dt])
    # mod at stamps near 2e9 loses about 2.4e-7 s; at 1.5 m/s that is well under a micrometre.
    assert math.dist(a[:2], b[:2]) <= speed * dt + 1e-6
    legs = np.array(walk.legs)
    for pose in (a, b):
        gaps = [np.hypot(*(pose[:2] - closest)) for closest in _closest_on_legs(pose[:2], legs)]
        assert min(gaps) < 1e-6                       # on one of its legs, never cutting a corner


def _closest_on_legs(point: np.ndarray, legs: np.ndarray) -> list[np.ndarray]:
    result = []
    for start, end in legs:
        edge = end - start
        f = np.clip(np.dot(point - start, edge) / np.dot(edge, edge), 0.0, 1.0)
        result.append(start + f * edge)
    return result


@settings(max_examples=100, deadline=None)
@given(points=waypoints, speed=st.floats(0.05, MAX_SPEED), pause=st.floats(0.0, 5.0),
       mode=st.sampled_from([LOOP, BACK_AND_FORTH]))
def test_one_cycle_stands_pause_at_every_waypoint_and_walks_every_leg(
        points: list[tuple[float, float]], speed: float, pause: float, mode: str) -> None:
    try:
        walk = Walk(tuple(points), speed, pause, mode)
    except ValueError:
        return
    lengths = [math.dist(a, b) for a, b in walk.legs]
    assert walk.cycle == pytest.approx(len(lengths) * pause + sum(lengths) / speed)
    # Sampled finely over a cycle, the path's length is the legs' (no jump, no shortcut).
    stamps = NOW + np.linspace(0.0, walk.cycle, 20001)
    xy = walk.poses_at(stamps)[:, :2]
    travelled = float(np.sum(np.hypot(*np.diff(xy, axis=0).T)))
    assert travelled == pytest.approx(sum(lengths), rel=1e-3, abs=1e-5)
    assert np.allclose(xy[0], xy[-1], atol=1e-5)   # a cycle ends where it began
