"""Timing the passage past walkers (:func:`pluto_motion.passage.passage_speed`): nothing to do when
the speed wanted keeps clear, wait short of a walker about to cross ahead, go on past one coming at
the robot's side, back off from one coming at it only when allowed to."""

from __future__ import annotations

import numpy as np
import pytest

from pluto_motion.passage import PassageSettings, Walker, passage_speed


def walker(x: float, y: float, vx: float, vy: float, radius: float = 0.25) -> Walker:
    """A person at (x, y) in the robot frame walking at (vx, vy)."""
    return Walker(np.array([x, y]), radius, np.array([vx, vy]))


def test_no_walker_or_one_out_of_the_way_leaves_the_speed_alone() -> None:
    assert passage_speed([], 0.6, 0.6) is None
    assert passage_speed([walker(3.0, 2.0, 1.0, 0.0)], 0.6, 0.6) is None          # walking along, apart
    assert passage_speed([walker(2.0, -1.0, 0.0, -1.0)], 0.6, 0.6) is None        # walking away


def test_a_walker_about_to_cross_ahead_is_waited_for() -> None:
    settings = PassageSettings()
    speed, gap = passage_speed([walker(1.6, -1.2, 0.0, 0.8)], 0.6, 0.6, settings)
    assert 0.0 <= speed < 0.6 and gap >= settings.margin


def test_a_walker_coming_at_the_side_is_left_behind() -> None:
    """Crossing where the robot is now: stopping would be met, so the robot goes on, at its speed
    or speeding up from a slower one."""
    side = [walker(0.0, -1.6, 0.0, 1.0)]
    stopping = passage_speed(side, 0.6, 0.0, PassageSettings(back=0.0))
    assert stopping is not None and stopping[1] < 0.0, 'no test: stopping would not be met'
    assert passage_speed(side, 0.6, 0.6) is None
    speeding = passage_speed(side, 0.3, 0.6)
    assert speeding is None or speeding[0] == pytest.approx(0.6)


def test_one_coming_at_the_robot_is_backed_off_from_only_when_allowed() -> None:
    head_on = [walker(2.0, 0.0, -0.5, 0.0)]
    backing, _ = passage_speed(head_on, 0.0, 0.6, PassageSettings(back=0.3))
    assert backing < 0.0
    standing, _ = passage_speed(head_on, 0.0, 0.6, PassageSettings(back=0.0))
    assert standing == 0.0


def test_a_robot_standing_steps_out_of_the_way_of_one_coming_at_its_side() -> None:
    side = [walker(-0.2, -3.0, 0.0, 1.0)]
    speed, gap = passage_speed(side, 0.0, 0.0, PassageSettings(back=0.0), ahead=0.3)
    assert 0.0 < speed <= 0.3 and gap >= PassageSettings().margin
    held, gap = passage_speed(side, 0.0, 0.0, PassageSettings(back=0.0), ahead=0.0)   # a wall ahead
    assert held == 0.0 and gap < 0.0
