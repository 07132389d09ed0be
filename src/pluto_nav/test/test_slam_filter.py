"""SlamFilter: maps built in the simulator match the world, the pose stays on the truth, the saved
map loads and localizes a PoseFilter; small deterministic cases for the map bookkeeping."""

from __future__ import annotations

import math

import numpy as np
import pytest
import random_maps
import slam_sim
from nav_sim import MOUNT
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.mapfile import load_map
from wurde_drivers.sim.world import World
from wurde_idl.mapfile import load_map_data, save_map_data

from pluto_nav.geometry import compose
from pluto_nav.lines import extract_lines
from pluto_nav.slam_filter import LINE_EXTRACTION, SlamFilter, SlamSettings
from pluto_nav.slam_merge import MergeSettings

MAPS = slam_sim.__file__.rsplit('/src/', 1)[0] + '/config/maps'


def _scan_lines(world: World, pose: tuple[float, float, float]) -> list:
    """The lines a noiseless laser at ``pose`` (its own frame) sees."""
    laser = LaserModel(LaserGeometry(), np.random.default_rng(0))
    return extract_lines(laser.scan(world, *pose), range_sigma=0.005, **LINE_EXTRACTION)


# -- small cases ----------------------------------------------------------------------------------

def test_first_scan_maps_the_walls_in_view() -> None:
    room = World([(0, 0, 8, 0), (8, 0, 8, 6), (8, 6, 0, 6), (0, 6, 0, 0)])
    slam = SlamFilter(settings=SlamSettings(confirm_matches=1))
    slam.set_pose((2.0, 3.0, 0.0), np.zeros((3, 3)))
    result = slam.update(_scan_lines(room, (2.0, 3.0, 0.0)))
    assert (result.added, result.matched, len(slam)) == (3, 0, 3)
    walls = slam.walls()
    assert len(walls) == 3
    assert slam_sim.wall_errors(walls, room).max() < 0.02
    # The part seen: right, ahead and left of the laser, not the wall behind it.
    assert min(walls[:, [0, 2]].min(axis=1)) > 1.5


def test_ends_are_tied_to_confirmed_walls_at_corners_only() -> None:
    """An end tied to a crossing wall moves with that wall's corrections: right at a corner of
    walls known well, wrong anywhere else (a door jamb tied to a wall 0.5 m off moved 20 cm)."""
    room = World([(0, 0, 8, 0), (8, 0, 8, 6), (8, 6, 0, 6), (0, 6, 0, 0)])
    slam = SlamFilter()
    pose = (2.0, 3.0, 0.0)
    slam.set_pose(pose, np.zeros((3, 3)))
    lines = _scan_lines(room, pose)

    def ends() -> list:
        return [end for mark in slam._marks.values() for end in (mark.extent.lo, mark.extent.hi)]
    slam.update(lines)
    assert len(ends()) == 6 and all(end.anchor is None for end in ends())   # all three tentative
    for _ in range(slam.settings.confirm_matches):
        slam.predict((0.0, 0.0, 0.0), np.diag([1e-6, 1e-6, 1e-8]))
        slam.update(lines)
    tied = [end for end in ends() if end.anchor is not None]
    # The corners (8, 0) and (8, 6), two ends each; the side walls' ends beside the laser are free.
    assert len(tied) == 4 and max(abs(end.offset) for end in tied) < 0.3


def test_walls_seen_again_are_matched_not_added() -> None:
    room = World([(0, 0, 8, 0), (8, 0, 8, 6), (8, 6, 0, 6), (0, 6, 0, 0)])
    slam = SlamFilter()
    slam.set_pose((2.0, 3.0, 0.0), np.zeros((3, 3)))
    slam.update(_scan_lines(room, (2.0, 3.0, 0.0)))
    # The robot moved 0.5 m; odometry says 0.45 m.
    slam.predict((0.45, 0.0, 0.0), np.diag([0.05 ** 2, 0.01 ** 2, 0.01 ** 2]))
    result = slam.update(_scan_lines(room, (2.5, 3.0, 0.0)))
    assert (result.matched, result.added) == (3, 0)
    assert slam.pose == pytest.approx([2.5, 3.0, 0.0], abs=0.005)


@pytest.mark.parametrize('gap, merged', [(0.5, False), (0.8, True)])
def test_collinear_pieces_merge_when_their_extents_meet(gap: float, merged: bool) -> None:
    # A wall ahead with a 0.6 m door in it: two lines in the scan, two landmarks at first.
    world = World([(4, -3, 4, -0.3), (4, 0.3, 4, 3), (6, -3, 6, 3)])
    settings = SlamSettings(confirm_matches=1, merge=MergeSettings(gap=gap))
    slam = SlamFilter(settings=settings)
    slam.set_pose((0.0, 0.0, 0.0), np.zeros((3, 3)))
    result = slam.update(_scan_lines(world, (0.0, 0.0, 0.0)))
    assert result.merged == int(merged)
    near = [w for w in slam.walls() if abs(w[0] - 4.0) < 0.05 and abs(w[2] - 4.0) < 0.05]
    assert len(near) == (1 if merged else 2)


def test_a_wall_seen_briefly_is_pruned() -> None:
    room = [(0, 0, 8, 0), (8, 0, 8, 6), (8, 6, 0, 6), (0, 6, 0, 0)]
    cart = [(5, 2.5, 5, 3.5)]                          # in view for two scans, then gone
    settings = SlamSettings(confirm_matches=4, tentative_scans=5)
    slam = SlamFilter(settings=settings)
    slam.set_pose((2.0, 3.0, 0.0), np.zeros((3, 3)))
    pruned = []
    for scan in range(12):
        if scan:
            slam.predict((0.0, 0.0, 0.0), np.diag([1e-6, 1e-6, 1e-6]))
        world = World(room + cart) if scan < 2 else World(room)
        pruned.append(slam.update(_scan_lines(world, (2.0, 3.0, 0.0))).pruned)
    assert sum(pruned) == 1 and pruned.index(1) == 1 + settings.tentative_scans
    assert len(slam) == 3
    assert not any(abs(w[0] - 5.0) < 0.05 and abs(w[2] - 5.0) < 0.05 for w in slam.walls())


def test_to_map_data_has_the_robot_start() -> None:
    slam = SlamFilter()
    slam.set_pose(compose((1.0, 2.0, 0.5), MOUNT), np.zeros((3, 3)))
    data = slam.to_map_data('empty', mount=MOUNT)
    assert data.name == 'empty' and data.walls == ()
    assert tuple(data.places['start']) == pytest.approx((1.0, 2.0, 0.5))


def test_bad_input_is_refused() -> None:
    slam = SlamFilter()
    with pytest.raises(ValueError, match='finite'):
        slam.set_pose((0.0, math.nan, 0.0), np.zeros((3, 3)))
    with pytest.raises(ValueError, match='semi-definite'):
        slam.set_pose((0.0, 0.0, 0.0), -np.eye(3))
    with pytest.raises(ValueError, match='symmetric'):
        slam.predict((0.1, 0.0, 0.0), [[1, 2, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(ValueError, match='finite'):
        slam.predict((math.inf, 0.0, 0.0), np.eye(3))
    with pytest.raises(ValueError, match='extent_range'):
        SlamSettings(max_range=5.0, extent_range=8.0)
    with pytest.raises(ValueError, match='odometry_inflation'):
        SlamSettings(odometry_inflation=0.5)


# -- simulator runs -------------------------------------------------------------------------------

@pytest.fixture(scope='module')
def office_run() -> slam_sim.SlamRun:
    world = load_map(f'{MAPS}/office.xml')
    route = slam_sim.loop_route(world, 25.0, np.random.default_rng(3))
    return slam_sim.run(world, route, seed=3, check_every=25)


def test_office_loop_pose_and_walls(office_run: slam_sim.SlamRun) -> None:
    run = office_run
    rmse_xy, rmse_theta, odo_xy, _ = run.rmse()
    assert run.driven > 30.0
    assert rmse_xy < 0.05 and rmse_theta < math.radians(0.5)
    assert run.error_xy.max() < 0.10
    assert odo_xy > 10 * rmse_xy                  # the map is what keeps the pose
    walls = run.filter.walls()
    assert len(walls) >= 20
    assert slam_sim.wall_errors(walls, run.world).max() < 0.10
    assert slam_sim.wall_errors_same_wall(walls, run.world).max() < 0.10
    assert run.spd


def test_saved_map_loads_and_localizes(office_run: slam_sim.SlamRun, tmp_path) -> None:
    data = office_run.filter.to_map_data('office-slam', mount=MOUNT)
    path = tmp_path / 'office-slam.xml'
    save_map_data(data, path)
    loaded = load_map_data(path)
    assert loaded.walls == data.walls and len(loaded.walls) >= 20
    start = office_run.world.place('start')
    assert tuple(loaded.places['start']) == pytest.approx(tuple(start), abs=1e-9)
    route = slam_sim.loop_route(office_run.world, 15.0, np.random.default_rng(8))
    errors = slam_sim.localize(office_run.world, np.array(loaded.walls), loaded.places['start'],
                               route, seed=8)
    assert len(errors) > 50
    assert float(np.sqrt(np.mean(errors ** 2))) < 0.05 and errors.max() < 0.10


def test_random_map_loop() -> None:
    world = random_maps.random_map(5)
    route = slam_sim.loop_route(world, 12.0, np.random.default_rng(5))
    run = slam_sim.run(world, route, seed=5, check_every=40)
    rmse_xy, rmse_theta, odo_xy, _ = run.rmse()
    assert run.driven > 20.0
    assert rmse_xy < 0.05 and rmse_theta < math.radians(0.5) and run.error_xy.max() < 0.10
    assert odo_xy > 10 * rmse_xy
    walls = run.filter.walls()
    assert len(walls) >= 10
    assert slam_sim.wall_errors(walls, world).max() < 0.10
    assert slam_sim.wall_errors_same_wall(walls, world).max() < 0.10
    assert run.spd


def test_compression_changes_nothing() -> None:
    """With a short laser range and a small local area the compressed filter works on part of
    the map and commits often; pose and map come out as with one local area for everything
    (the plain EKF)."""
    world = random_maps.random_map(4)
    route = slam_sim.loop_route(world, 8.0, np.random.default_rng(4))
    runs = [slam_sim.run(world, route, seed=4, length_m=20.0, settings=SlamSettings(
        max_range=8.0, extent_range=8.0, zone_radius=zone)) for zone in (1.0, 1e6)]
    compressed, whole = runs
    assert sum(u.committed for u in compressed.updates) >= 5
    assert any(u.active < u.landmarks for u in compressed.updates)
    assert not any(u.committed for u in whole.updates)
    assert all(u.active == u.landmarks for u in whole.updates)
    mean, cov = compressed.filter.state()
    whole_mean, whole_cov = whole.filter.state()
    np.testing.assert_allclose(mean, whole_mean, atol=1e-8)
    np.testing.assert_allclose(cov, whole_cov, atol=1e-12)
    np.testing.assert_allclose(compressed.filter.walls(), whole.filter.walls(), atol=1e-8)
