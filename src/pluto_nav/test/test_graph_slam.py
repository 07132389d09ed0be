"""Scan-matching graph SLAM (the slamModule's ``scans`` method): its parts on small exact cases,
and whole runs in the simulator with noise on, on a shipped map and a generated one."""

from __future__ import annotations

import math

import numpy as np
import pytest
import random_maps
import slam_sim
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.mapfile import load_map
from wurde_drivers.sim.world import World

from pluto_nav.correlative import Window, search
from pluto_nav.geometry import compose, relative, transform_points, wrap
from pluto_nav.graph_slam import GraphSlam
from pluto_nav.icp import refine
from pluto_nav.lines import scan_points
from pluto_nav.occupancy import OCCUPIED, build_grid, grid_walls
from pluto_nav.point_map import PointMap, voxel_filter
from pluto_nav.pose_graph import Edge, PoseGraph

MAPS = slam_sim.__file__.rsplit('/src/', 1)[0] + '/config/maps'
ROOM = World([(0, 0, 10, 0), (10, 0, 10, 7), (10, 7, 0, 7), (0, 7, 0, 0), (6, 2, 7, 2), (6, 2, 6, 3),
              (2, 5, 3.5, 5.5)])
ANGLES = np.linspace(-math.pi / 2, math.pi / 2, 361)


def _points(world: World, pose: tuple[float, float, float], seed: int = 0) -> np.ndarray:
    ranges = LaserModel(LaserGeometry(noise_sigma=0.01), np.random.default_rng(seed)).scan(world, *pose)
    _, _, x, y, _ = scan_points(np.asarray(ranges), angles=ANGLES, max_range=30.0)
    return np.column_stack([x, y])


def _chain(n: int) -> np.ndarray:
    """A robot driving round a circle of about 9.5 m in ``n`` steps of 0.3 m."""
    poses = np.zeros((n, 3))
    for k in range(1, n):
        poses[k] = compose(poses[k - 1], (0.3, 0.0, 0.02))
    return poses


# -- the pose graph ---------------------------------------------------------------------------

def test_the_pose_graph_closes_a_loop_to_the_truth() -> None:
    truth = _chain(400)
    rng = np.random.default_rng(1)
    graph = PoseGraph()
    graph.add_node(truth[0])
    step_info = np.diag([1e4, 1e4, 4e4])
    for k in range(1, len(truth)):
        z = relative(truth[k - 1], truth[k]) + rng.normal(0, [0.01, 0.01, 0.005])
        graph.add_node(compose(graph.poses[-1], z))
        graph.add_edge(Edge(k - 1, k, tuple(z), step_info))
    drifted = np.abs(graph.poses[-1, :2] - truth[-1, :2]).max()
    for k in range(320, 400, 20):                      # the robot is back where it was 314 steps ago
        graph.add_edge(Edge(k - 314, k, tuple(relative(truth[k - 314], truth[k])), step_info * 10, 3.0, 'loop'))
    solution = graph.optimize(iterations=20)
    closed = np.abs(graph.poses[-1, :2] - truth[-1, :2]).max()
    assert drifted > 0.5 and closed < 0.1 * drifted
    assert solution.iterations < 20 and (solution.weights == 1.0).all()


def test_a_wrong_loop_closure_among_right_ones_is_down_weighted() -> None:
    truth = _chain(400)
    graph = PoseGraph()
    info = np.diag([1e4, 1e4, 4e4])
    graph.add_node(truth[0])
    for k in range(1, len(truth)):
        graph.add_node(truth[k])
        graph.add_edge(Edge(k - 1, k, tuple(relative(truth[k - 1], truth[k])), info))
    for k in range(320, 400, 10):
        graph.add_edge(Edge(k - 314, k, tuple(relative(truth[k - 314], truth[k])), info, 3.0, 'loop'))
    wrong = relative(truth[40], truth[355]) + np.array([0.8, -0.5, 0.1])
    graph.add_edge(Edge(40, 355, tuple(wrong), info, 3.0, 'loop'))
    solution = graph.optimize(iterations=30)
    assert solution.weights[-1] < 0.1 and (solution.weights[:-1] > 0.5).all()
    assert np.abs(graph.poses[:, :2] - truth[:, :2]).max() < 0.1


def test_an_edge_of_unknown_nodes_is_refused() -> None:
    graph = PoseGraph()
    graph.add_node((0, 0, 0))
    with pytest.raises(ValueError, match='edge 0 -> 1'):
        graph.add_edge(Edge(0, 1, (1.0, 0.0, 0.0), np.eye(3)))


# -- matching ---------------------------------------------------------------------------------

def test_correlative_search_and_icp_find_a_scan_off_by_a_third_of_a_metre() -> None:
    here = (3.0, 3.0, 0.3)
    reference = PointMap(voxel_filter(transform_points(here, _points(ROOM, here)), 0.05), resolution=0.1, sigma=0.1)
    moved = (3.4, 3.1, 0.38)
    scan = voxel_filter(_points(ROOM, moved, seed=1), 0.1)
    guess = np.array([3.15, 2.9, 0.3])                 # 0.27 m and 4.6 degrees off
    best = search(reference, scan, guess, Window(0.4, math.radians(8)))[0]
    result = refine(reference, scan, np.array(best.pose))
    assert result.ok and result.inliers > 0.9
    assert math.dist(result.pose[:2], moved[:2]) < 0.02
    assert abs(wrap(result.pose[2] - moved[2])) < math.radians(0.3)
    # Along a corridor the information is small, across it large.
    corridor = World([(0, 0, 30, 0), (0, 2, 30, 2)])
    inside = PointMap(voxel_filter(transform_points((10, 1, 0), _points(corridor, (10, 1, 0))), 0.05))
    along = refine(inside, voxel_filter(_points(corridor, (10.1, 1, 0), seed=2), 0.1), np.array([10.1, 1.0, 0.0]))
    assert along.information[1, 1] > 30 * along.information[0, 0]


def test_a_point_map_needs_points() -> None:
    with pytest.raises(ValueError, match='needs 7 points'):
        PointMap(np.zeros((3, 2)))


# -- whole runs --------------------------------------------------------------------------------

def _slam(world: World, length: float, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, GraphSlam]:
    """Graph SLAM along a loop in ``world``; per scan: the estimated and true laser poses, and the
    odometry's; the SLAM at the end."""
    route = slam_sim.loop_route(world, length, np.random.default_rng(seed))
    slam = GraphSlam()
    truth, dead = [], []
    for k, scan in enumerate(slam_sim.drive(world, route, seed=seed)):
        if k == 0:
            slam.set_pose(scan.truth)
        else:
            slam.predict(scan.increment)
        slam.update_ranges(scan.ranges, ANGLES, max_range=LaserGeometry().max_range)
        truth.append(scan.truth)
        dead.append(scan.dead_reckoning)
    slam.finish()
    return slam.trajectory(), np.array(truth), np.array(dead), slam


def _errors(estimate: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    return (float(np.sqrt(np.mean(np.sum((estimate[:, :2] - truth[:, :2]) ** 2, axis=1)))),
            float(np.sqrt(np.mean(wrap(estimate[:, 2] - truth[:, 2]) ** 2))))


@pytest.fixture(scope='module')
def office() -> tuple:
    return _slam(load_map(f'{MAPS}/office.xml'), 25.0, 3)


def test_the_office_loop_is_mapped_on_the_truth(office: tuple) -> None:
    estimate, truth, dead, slam = office
    assert len(estimate) == len(truth) > 100
    xy, theta = _errors(estimate, truth)
    odo_xy, _ = _errors(dead, truth)
    assert xy < 0.05 and theta < math.radians(0.5)
    assert odo_xy > 5 * xy
    assert slam.closures >= 1


def test_the_map_s_walls_lie_on_the_true_walls(office: tuple) -> None:
    _, _, _, slam = office
    world = load_map(f'{MAPS}/office.xml')
    grid = build_grid(slam.graph.poses, [(n.angles, n.ranges) for n in slam.nodes], resolution=0.05)
    occupied = grid.occupied_points
    assert len(occupied) > 500
    off = np.array([world.distance_to_nearest_wall(p) for p in occupied])
    assert np.percentile(off, 95) < 0.06                   # a cell, and the scans' noise
    assert (grid.cells == OCCUPIED).sum() < 0.2 * grid.cells.size
    walls = grid_walls(grid)                                # the outlines of the occupied cells
    assert len(walls) >= 20
    assert np.percentile(slam_sim.wall_errors(walls, world), 90) < 0.1


def test_a_generated_map_is_mapped_on_the_truth() -> None:
    world = random_maps.random_map(5)
    estimate, truth, dead, slam = _slam(world, 12.0, 5)
    xy, theta = _errors(estimate, truth)
    assert xy < 0.05 and theta < math.radians(0.5)
    assert _errors(dead, truth)[0] > 3 * xy


def test_the_same_scans_give_the_same_map() -> None:
    world = random_maps.random_map(7)
    first, _, _, _ = _slam(world, 6.0, 7)
    second, _, _, _ = _slam(world, 6.0, 7)
    assert np.array_equal(first, second)
