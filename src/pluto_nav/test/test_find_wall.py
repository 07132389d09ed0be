"""Pluto 7.1's "find the longest wall in front of the robot"."""

import math

import numpy as np
import pytest
from test_lines import wall_ranges

from pluto_nav.find_wall import find_wall
from pluto_nav.lines import extract_lines


def test_the_wall_with_most_points_ahead_is_found():
    # Ahead: x = 3 (gamma 0) and a wall turned 30 degrees to the left with fewer points.
    ranges = wall_ranges(0.0, 3.0, (-1.5, 0.3))
    ranges = wall_ranges(math.radians(30), 2.5, (0.5, 2.0), ranges=ranges)
    # Beside the laser on the right (gamma -90 degrees): close, with the most points.
    ranges = wall_ranges(-math.pi / 2, 0.5, (0.2, 0.9), ranges=ranges)
    lines = extract_lines(ranges)
    side = [line for line in lines if abs(line.gamma + math.pi / 2) < 0.01]
    ahead = [line for line in lines if abs(line.gamma) < math.radians(45)]
    assert side and len(ahead) == 2
    assert side[0].points > max(line.points for line in ahead)
    found = find_wall(lines)
    assert found is not None
    best = max(ahead, key=lambda line: line.points)
    assert (found.points, found.gamma, found.rho) == (best.points, best.gamma, best.rho)
    assert np.array_equal(found.covariance, best.covariance)
    params = found.parameters()
    assert len(params) == 6 and params[:2] == [found.gamma, found.rho]
    assert params[2:] == found.covariance.reshape(4).tolist()


def test_nothing_in_front():
    ranges = wall_ranges(math.pi / 2, 1.0, (-4.0, 1.0))          # only a wall to the left
    assert find_wall(extract_lines(ranges)) is None
    assert find_wall([]) is None
    # A narrower "in front" can exclude a wall the default keeps.
    ranges = wall_ranges(math.radians(30), 2.0, (-1.0, 1.0))
    assert find_wall(extract_lines(ranges)) is not None
    assert find_wall(extract_lines(ranges), front_angle=math.radians(20)) is None


def test_a_bad_front_angle_is_refused():
    with pytest.raises(ValueError):
        find_wall([], front_angle=2.0)
