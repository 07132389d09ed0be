"""The map's walls: normal form, extents, collinear chains, what a laser can see."""

import math

import numpy as np
import pytest

from pluto_nav.wall_map import WallMap


def test_walls_in_normal_form_with_extents():
    walls = WallMap([(2, -1, 2, 3),            # x = 2
                     (0, 5, 4, 5),             # y = 5
                     (-3, 0, -3, 2)])          # x = -3: normal points to -x
    assert np.allclose(walls.gamma, [0.0, math.pi / 2, math.pi])
    assert np.allclose(walls.rho, [2.0, 5.0, 3.0])
    assert np.allclose(walls.length, [4.0, 4.0, 2.0])
    # Extents along (-sin gamma, cos gamma), measured from the foot of the perpendicular.
    assert np.allclose(walls.extent, [(-1, 3), (-4, 0), (-2, 0)])
    assert np.allclose(walls.cos_gamma ** 2 + walls.sin_gamma ** 2, 1.0)


def test_collinear_walls_share_a_line_and_touching_ones_a_chain():
    walls = WallMap([(0, 0, 2, 0), (2, 0, 5, 0),     # touching pieces of y = 0
                     (6, 0, 8, 0),                   # the same line after a 1 m gap (a door)
                     (8.0, 0.1, 9, 0.1),             # parallel, 0.1 m off: another line
                     (9, 0, 7.5, 0)])                # drawn backwards, overlapping the third
    assert walls.line[0] == walls.line[1] == walls.line[2] == walls.line[4]
    assert walls.line[3] != walls.line[0]
    assert np.allclose(walls.chain_length, [5, 5, 3, 1, 3])
    # A chain's extent is in each wall's own coordinate along it.
    t = np.array([(0, 0), (5, 0)]) @ np.array([-walls.sin_gamma[0], walls.cos_gamma[0]])
    assert np.allclose(sorted(walls.chain_extent[0]), sorted(t))
    t = np.array([(6, 0), (9, 0)]) @ np.array([-walls.sin_gamma[4], walls.cos_gamma[4]])
    assert np.allclose(sorted(walls.chain_extent[4]), sorted(t))


def test_visible_walls_are_in_range_ahead_and_not_edge_on():
    walls = WallMap([(5, -1, 5, 1),        # 0: ahead
                     (-5, -1, -5, 1),      # 1: behind
                     (50, -1, 50, 1),      # 2: ahead, beyond 20 m
                     (1, 0, 4, 0),         # 3: on the laser's own line (edge-on)
                     (0.5, 2, 3, 2)])      # 4: to the left, partly ahead
    assert walls.visible((0, 0, 0), 20.0).tolist() == [0, 4]
    assert walls.visible((0, 0, math.pi), 20.0).tolist() == [1]
    assert walls.visible((0, 0, 0), 60.0).tolist() == [0, 2, 4]
    # The margin lets a wall just behind count (the pose is uncertain).
    assert 1 in walls.visible((-4.5, 2, math.pi / 2), 20.0, margin=1.5)
    assert 1 not in walls.visible((-4.5, 2, math.pi / 2), 20.0)


@pytest.mark.parametrize('walls, message', [
    (np.ones((2, 3)), r'\(N, 4\)'),
    ([(0, 0, math.nan, 1)], 'wall 0 has a non-finite'),
    ([(0, 0, 1, 1), (2, 2, 2, 2)], 'wall 1 has zero length'),
])
def test_bad_walls_are_refused(walls, message):
    with pytest.raises(ValueError, match=message):
        WallMap(walls)


def test_an_empty_map_sees_nothing():
    walls = WallMap(np.zeros((0, 4)))
    assert len(walls) == 0
    assert walls.visible((0, 0, 0), 10.0).tolist() == []
