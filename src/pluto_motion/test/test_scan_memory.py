"""pluto_motion.scan_memory: the points earlier scans saw near the robot that the laser cannot see
now — kept where they are in the world, forgotten when in view again, too far, or after the robot
has moved far enough for the odometry's error to matter (never for standing)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, strategies as st

from pluto_motion.scan_memory import LaserView, ScanMemory, moved

#: A 180-degree laser 0.2 m ahead of the centre, as chapter 1's robot has.
VIEW = LaserView(0.2, 0.0, -math.pi / 2, math.pi / 2, 8.0)
NOTHING = np.empty((0, 2))


def test_a_point_seen_ahead_is_given_back_behind_once_the_robot_has_turned() -> None:
    memory = ScanMemory()
    memory.add((1.0, 2.0, 0.0), np.array([[0.6, 0.0]]), VIEW)     # (1.6, 2.0) in the world
    assert len(memory.unseen((1.0, 2.0, 0.0), VIEW)) == 0           # the scan has it: not repeated
    memory.add((1.0, 2.0, math.pi), NOTHING, VIEW)                  # turned round: out of view
    unseen = memory.unseen((1.0, 2.0, math.pi), VIEW)
    assert np.allclose(unseen, [[-0.6, 0.0]])


def test_a_point_in_view_again_is_what_the_latest_scan_says() -> None:
    """Something that has gone (a person walked off) is not remembered where the laser looks."""
    memory = ScanMemory()
    memory.add((0.0, 0.0, 0.0), np.array([[0.5, 0.1]]), VIEW)
    memory.add((0.0, 0.0, 0.0), NOTHING, VIEW)                      # seen empty
    memory.add((0.0, 0.0, math.pi), NOTHING, VIEW)
    assert len(memory.unseen((0.0, 0.0, math.pi), VIEW)) == 0


def test_points_are_kept_while_the_robot_stands_and_forgotten_after_it_has_moved_or_when_far() -> None:
    """A standing robot keeps a box beside it however long it stands (bench/guide_avoider.py at
    9600 baud: a box forgotten after 5 s of standing was touched); driving and turning wear the
    memory out (the odometry's error grows with motion); a point 1 m or more away is not kept."""
    memory = ScanMemory(near=1.0, keep_m=4.0)
    memory.add((0.0, 0.0, 0.0), np.array([[0.5, 0.0], [1.5, 0.0]]), VIEW)        # 1.5 m: not kept
    memory.add((0.0, 0.0, math.pi), NOTHING, VIEW)                              # a half turn: 3.14
    for _ in range(1000):                                                      # standing, looking away
        assert np.allclose(memory.unseen((0.0, 0.0, math.pi), VIEW), [[-0.5, 0.0]])
    memory.add((-0.3, 0.0, math.pi), NOTHING, VIEW)                             # 0.3 m on: 3.44
    assert np.allclose(memory.unseen((-0.3, 0.0, math.pi), VIEW), [[-0.8, 0.0]])
    memory.add((-0.3, 0.0, math.pi - 0.6), NOTHING, VIEW)                       # 0.6 rad more: 4.04
    assert len(memory.unseen((-0.3, 0.0, math.pi - 0.6), VIEW)) == 0
    memory = ScanMemory(near=1.0, keep_m=4.0)
    memory.add((0.0, 0.0, 0.0), np.array([[0.5, 0.0]]), VIEW)
    memory.add((0.0, 0.0, math.pi), NOTHING, VIEW)
    assert len(memory.unseen((-0.8, 0.0, math.pi), VIEW)) == 0                  # now 1.3 m away


def test_one_point_is_kept_per_cell_the_newest() -> None:
    memory = ScanMemory(cell=0.05)
    memory.add((0.0, 0.0, 0.0), np.array([[0.51, 0.01], [0.52, 0.02]]), VIEW)
    memory.add((0.0, 0.0, math.pi), NOTHING, VIEW)
    assert len(memory) == 1


@given(st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi))
def test_the_view_sees_a_bearing_when_it_is_within_the_fan_whatever_the_turns(middle: float, bearing: float) -> None:
    """A fan of 100 degrees round ``middle``, even across +-pi, sees a point 1 m from the laser
    at ``bearing`` exactly when the bearing is within 50 degrees of the middle."""
    half = math.radians(50)
    view = LaserView(0.0, 0.0, middle - half, middle + half)
    point = np.array([[math.cos(bearing), math.sin(bearing)]])
    off = abs(math.remainder(bearing - middle, math.tau))
    if abs(off - half) > 1e-9:
        assert bool(view.sees(point)[0]) == (off < half)


def test_a_scan_taken_before_a_turn_is_moved_to_where_the_robot_is_now() -> None:
    """A box 1 m ahead when the scan was taken, the robot since turned 0.2 rad left (a 0.2 s old
    scan at 1 rad/s) and moved 0.1 m on: the box is now right of its heading, not ahead."""
    now = moved(np.array([[1.0, 0.0]]), (0.0, 0.0, 0.0), (0.1, 0.0, 0.2))[0]
    assert now == pytest.approx((0.9 * math.cos(0.2), -0.9 * math.sin(0.2)))
    assert len(moved(np.empty((0, 2)), (0.0, 0.0, 0.0), (1.0, 2.0, 3.0))) == 0
