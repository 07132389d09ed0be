"""The simulated world: ray casting against known walls, distances, disc motion, off-limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wurde_drivers.sim.world import World, points_in_polygon

ROOM = [(0, 0, 4, 0), (4, 0, 4, 3), (4, 3, 0, 3), (0, 3, 0, 0)]


def reference_raycast(walls, origin, angle, max_range):
    """One beam, one wall at a time, in plain Python: what the vectorised kernel must match."""
    ox, oy = origin
    dx, dy = math.cos(angle), math.sin(angle)
    best = max_range
    for x1, y1, x2, y2 in walls:
        ex, ey = x2 - x1, y2 - y1
        denominator = dx * ey - dy * ex
        if abs(denominator) < 1e-12:
            continue
        wx, wy = x1 - ox, y1 - oy
        t = (wx * ey - wy * ex) / denominator
        s = (wx * dy - wy * dx) / denominator
        if t >= 0 and 0 <= s <= 1:
            best = min(best, t)
    return best


@pytest.mark.parametrize('distance', [0.25, 1.0, 3.5, 12.0])
def test_perpendicular_wall_at_distance_d(distance: float) -> None:
    world = World([(distance, -5, distance, 5)])
    angles = np.array([0.0, math.atan2(1.0, distance), -math.atan2(2.0, distance)])
    ranges = world.raycast((0, 0), angles, max_range=50)
    expected = [distance, math.hypot(distance, 1.0), math.hypot(distance, 2.0)]
    np.testing.assert_allclose(ranges, expected, rtol=0, atol=1e-12)


def test_oblique_wall_matches_the_analytic_distance() -> None:
    world = World([(2, 0, 0, 2)])  # the line x + y = 2
    angles = np.linspace(0.0, math.pi / 2, 91)
    ranges = world.raycast((0, 0), angles, max_range=10)
    np.testing.assert_allclose(ranges, 2.0 / (np.cos(angles) + np.sin(angles)), atol=1e-12)
    assert ranges[45] == pytest.approx(math.sqrt(2.0), abs=1e-12)


def test_beam_parallel_to_a_wall_misses_it() -> None:
    world = World([(0, 1, 10, 1)])
    ranges = world.raycast((0, 0), [0.0, math.pi], max_range=30)
    assert list(ranges) == [30, 30]
    assert world.raycast((0, 0), [math.pi / 2], max_range=30)[0] == pytest.approx(1.0)


def test_beam_along_a_wall_from_its_line_meets_its_near_end() -> None:
    world = World([(2, 1, 10, 1)])
    assert world.raycast((-1, 1), [0.0], max_range=30)[0] == pytest.approx(3.0)
    assert world.raycast((12, 1), [math.pi], max_range=30)[0] == pytest.approx(2.0)
    assert world.raycast((-1, 1), [math.pi], max_range=30)[0] == 30


def test_a_beam_through_a_door_gap_meets_the_wall_behind() -> None:
    door = [(3, -5, 3, -0.45), (3, 0.45, 3, 5), (6, -5, 6, 5)]
    world = World(door)
    through = world.raycast((0, 0), [0.0, math.atan2(0.4, 3)], max_range=30)
    np.testing.assert_allclose(through, [6.0, math.hypot(6, 0.8)], atol=1e-12)
    frame = math.atan2(0.5, 3)  # just above the gap: meets the door frame at x = 3
    assert world.raycast((0, 0), [frame], max_range=30)[0] == pytest.approx(math.hypot(3, 0.5))


def test_nothing_in_range_gives_max_range() -> None:
    world = World(ROOM)
    angles = np.linspace(-math.pi, math.pi, 361)
    assert np.all(world.raycast((2, 1.5), angles, max_range=1.0) == 1.0)
    assert np.all(World([(10, 10, 11, 10)]).raycast((0, 0), [math.pi], max_range=8) == 8)
    assert World().raycast((0, 0), [0.0, 1.0]).tolist() == [math.inf, math.inf]
    assert World([(5, -1, 5, 1)]).raycast((0, 0), [math.pi])[0] == math.inf


def test_origin_exactly_on_a_wall_gives_zero() -> None:
    world = World([(0, -1, 0, 1), (5, -5, 5, 5)])
    angles = np.linspace(-math.pi, math.pi, 73)  # includes beams along the wall (+-pi/2)
    assert np.all(world.raycast((0, 0), angles, max_range=30) == 0.0)
    oblique = World([(0, 0, 4, 4)])
    assert np.all(oblique.raycast((1, 1), angles, max_range=30) < 1e-9)


def test_the_kernel_matches_a_plain_reference_on_random_maps() -> None:
    rng = np.random.default_rng(7)
    centres = rng.uniform(0, 10, (60, 2))
    headings = rng.uniform(0, 2 * math.pi, 60)
    lengths = rng.uniform(0.2, 3.0, 60)
    walls = np.hstack([centres, centres + lengths[:, None] * np.column_stack(
        [np.cos(headings), np.sin(headings)])])
    world = World(walls)
    angles = np.linspace(-math.pi, math.pi, 181, endpoint=False)
    for origin in rng.uniform(0, 10, (5, 2)):
        ranges = world.raycast(origin, angles, max_range=8.0)
        expected = [reference_raycast(walls, origin, angle, 8.0) for angle in angles]
        np.testing.assert_allclose(ranges, expected, atol=1e-9)


def test_one_origin_per_beam_as_for_a_sonar_ring() -> None:
    world = World(ROOM)
    bearings = np.linspace(0, 2 * math.pi, 16, endpoint=False)
    origins = np.array([2, 1.5]) + 0.25 * np.column_stack([np.cos(bearings), np.sin(bearings)])
    ring = world.raycast(origins, bearings, max_range=10)
    one_by_one = [world.raycast(origin, [bearing], max_range=10)[0]
                  for origin, bearing in zip(origins, bearings)]
    np.testing.assert_allclose(ring, one_by_one, atol=1e-12)
    assert ring[0] == pytest.approx(4 - 2.25)  # east from x = 2.25 to the wall at x = 4
    with pytest.raises(ValueError, match='origin'):
        world.raycast(np.zeros((3, 2)), bearings)
    with pytest.raises(ValueError, match='finite'):
        world.raycast((math.nan, 0), bearings)


def test_nearest_wall_distance_and_point() -> None:
    world = World([(3, 0, 3, 2), (-5, 10, 5, 10)])
    assert world.distance_to_nearest_wall((1, 1)) == pytest.approx(2.0)
    assert world.distance_to_nearest_wall((3, 5)) == pytest.approx(3.0)  # past the end: corner
    distance, closest, index = world.nearest_wall((6, 9))
    assert (distance, index) == (pytest.approx(math.sqrt(2.0)), 1)
    np.testing.assert_allclose(closest, [5, 10])
    assert World().distance_to_nearest_wall((0, 0)) == math.inf


def test_circle_collides_and_segment_blocked() -> None:
    world = World([(3, -5, 3, -0.45), (3, 0.45, 3, 5)])
    assert world.circle_collides((2.6, 2), 0.4)
    assert not world.circle_collides((2.5, 2), 0.4)
    assert not world.segment_blocked((0, 0), (6, 0))  # through the door gap
    assert world.segment_blocked((0, 1), (6, 1))
    assert world.segment_blocked((0, 0.45), (3, 0.45))  # touching the door frame's end
    assert world.segment_blocked((3, 2), (3, 2))
    assert not world.segment_blocked((1, 1), (1, 1))


def test_first_contact_of_a_moving_disc() -> None:
    world = World([(3, -5, 3, 5), (-2, 2, 2, 2)])
    assert world.first_contact((0, 0), (5, 0), 0.5) == pytest.approx(0.5)   # stops at x = 2.5
    assert world.first_contact((0, 0), (1, 0), 0.5) == 1.0
    assert world.first_contact((2.5, 0), (3, 0), 0.5) == 0.0                 # touching: no further
    assert world.first_contact((2.5, 0), (1, 0), 0.5) == 1.0                 # backing away
    assert world.first_contact((2.5, 0), (2.5, -2), 0.5) == 1.0              # sliding along
    # Towards the free end of the second wall: the disc meets the rounded cap at (2, 2).
    fraction = world.first_contact((2.3, 4), (2.3, 0), 0.4)
    contact_y = 4 - fraction * 4
    assert contact_y > 2
    assert math.hypot(2.3 - 2, contact_y - 2) == pytest.approx(0.4, abs=1e-9)
    assert world.first_contact((2.5, 4), (2.5, 0), 0.4) == 1.0  # 0.5 from the cap: passes
    with pytest.raises(ValueError):
        world.first_contact((0, 0), (1, 0), -1)


def test_first_contact_agrees_with_sampled_distances_on_random_maps() -> None:
    rng = np.random.default_rng(11)
    centres = rng.uniform(0, 10, (40, 2))
    headings = rng.uniform(0, 2 * math.pi, 40)
    walls = np.hstack([centres, centres + 1.5 * np.column_stack([np.cos(headings),
                                                                  np.sin(headings)])])
    world = World(walls)
    radius, checked = 0.3, 0
    for start in rng.uniform(0, 10, (200, 2)):
        if world.distance_to_nearest_wall(start) <= radius:
            continue
        end = start + rng.uniform(-3, 3, 2)
        fraction = world.first_contact(start, end, radius)
        path = start + np.linspace(0, fraction, 100)[:, None] * (end - start)
        gaps = [world.distance_to_nearest_wall(point) for point in path]
        assert min(gaps) >= radius - 1e-9
        if fraction < 1.0:
            assert gaps[-1] == pytest.approx(radius, abs=1e-9)
            checked += 1
    assert checked > 10


def test_off_limits_point_in_polygon() -> None:
    ell = [(0, 0), (4, 0), (4, 1), (1, 1), (1, 4), (0, 4)]
    world = World(ROOM, offlimits=[ell, [(10, 10), (12, 10), (11, 12)]])
    assert world.is_off_limits((0.5, 3))
    assert world.is_off_limits((3, 0.5))
    assert not world.is_off_limits((2, 2))                      # in the notch of the L
    assert world.is_off_limits((11, 10.5))
    assert not world.is_off_limits((11.9, 11.9))
    mask = world.off_limits_mask([(0.5, 3), (2, 2), (11, 10.5)])
    assert mask.tolist() == [True, False, True]
    assert points_in_polygon([(0.5, 0.5), (5, 5)], ell).tolist() == [True, False]


def test_world_refuses_bad_input_and_compares_by_value() -> None:
    with pytest.raises(ValueError, match='zero length'):
        World([(1, 1, 1, 1)])
    with pytest.raises(ValueError, match='finite'):
        World([(0, 0, math.nan, 1)])
    with pytest.raises(ValueError, match='off-limits'):
        World(offlimits=[[(0, 0), (1, 1)]])
    world = World(ROOM, places={'start': (1, 1)}, name='room')
    assert world.place('start') == (1.0, 1.0, 0.0)
    assert world.bounds == (0, 0, 4, 3)
    assert world == World(ROOM, places={'start': (1, 1, 0)}, name='room')
    assert world != World(ROOM, places={'start': (1, 1, 0.1)}, name='room')
    assert world.is_free((1, 1), clearance=0.5) and not world.is_free((0.2, 1), clearance=0.5)
    with pytest.raises(KeyError, match='known: start'):
        world.place('kitchen')
    with pytest.raises(ValueError):
        world.walls[0, 0] = 5.0  # read-only: sensors share one world
