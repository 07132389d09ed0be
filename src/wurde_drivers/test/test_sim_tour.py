"""The tour's waypoint rule (wurde_drivers.sim.tour): reached, passed, or as near as the laser lets
the robot go — never a waypoint still far, nor one the laser has not stopped the robot short of."""

from __future__ import annotations

import math

from wurde_drivers.sim.tour import PASSED_M, REACHED_M, STOP_M, waypoint_reached


def test_near_or_passed_waypoints_are_reached() -> None:
    assert waypoint_reached(REACHED_M / 2, 0.5, math.inf) == ''
    assert waypoint_reached(PASSED_M / 2, 1.0, math.inf) == ''
    assert waypoint_reached(PASSED_M / 2, 0.9, math.inf) is None       # not passed, not near


def test_a_waypoint_the_laser_stops_the_robot_short_of_is_reached_with_the_reason() -> None:
    # make bench-nav's office run: 0.13 m from a waypoint 0.4 m from a wall, 0.44 m free ahead.
    assert 'as near as the laser allows' in waypoint_reached(0.13, 0.95, 0.44)
    assert waypoint_reached(0.13, 0.95, STOP_M + 0.01) is None          # the laser lets it go on
    assert waypoint_reached(PASSED_M + 0.01, 0.5, 0.2) is None           # still far: not reached
