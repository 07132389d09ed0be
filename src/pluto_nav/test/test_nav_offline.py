"""Localization in the simulator, short: a few tens of metres on the office map and on a random
map (``bench/nav_offline.py`` drives hundreds).  No ROS: the simulator runs in-process."""

import math
import pathlib

import pytest
from nav_sim import run
from random_maps import random_map
from wurde_drivers.sim.mapfile import load_map

MAPS = pathlib.Path(__file__).resolve().parents[3] / 'config' / 'maps'


@pytest.mark.parametrize('world', [load_map(MAPS / 'office.xml'), random_map(7)],
                         ids=lambda w: w.name)
def test_the_filter_tracks_the_robot_where_odometry_drifts(world):
    result = run(world, length_m=30.0, seed=21)
    assert result.driven >= 29.5 and not result.bumped
    xy, theta, odo_xy, odo_theta = result.rmse()
    assert xy <= 0.05 and theta <= math.radians(1.0)
    assert result.error_xy.max() < 0.2                      # never lost on the way
    assert odo_xy > 3 * xy and odo_theta > 3 * theta        # the baseline is much worse
    assert (result.matches[1:] > 0).mean() > 0.95


def test_a_wrong_start_is_corrected_within_five_metres():
    world = random_map(8)
    offset = (0.5 * math.cos(2.0), 0.5 * math.sin(2.0), math.radians(10.0))
    result = run(world, length_m=10.0, seed=22, offset=offset,
                 start_sigma=(0.5, math.radians(10.0)))
    assert result.error_xy[0] == pytest.approx(0.5)          # it really started off
    assert result.recovered_after(0.10) <= 5.0
    assert result.rmse(start_m=5.0)[0] < 0.05
