"""The poseModule's ``scans`` method (pluto_nav.localizers.ScanLocalizer): in the simulator with
noise on, from a start that is off, on a shipped map and a generated one; a map given as an
occupancy grid localizes as well as one given as walls."""

from __future__ import annotations

import math

import numpy as np
import random_maps
import slam_sim
from wurde_drivers.sim.laser import LaserGeometry
from wurde_drivers.sim.mapfile import load_map
from wurde_drivers.sim.world import World

from pluto_nav.estimation import Scan, ScanCycle
from pluto_nav.geometry import compose, wrap
from pluto_nav.localizers import ScanLocalizer, wall_points
from pluto_nav.occupancy import build_grid

MAPS = slam_sim.__file__.rsplit('/src/', 1)[0] + '/config/maps'
ANGLES = np.linspace(-math.pi / 2, math.pi / 2, 361)
OFF = (0.3, -0.25, math.radians(6.0))


def _localize(world: World, points: np.ndarray, seed: int, length: float) -> np.ndarray:
    """Position and heading errors per scan of a ScanLocalizer started ``OFF`` the truth."""
    route = slam_sim.loop_route(world, length, np.random.default_rng(seed))
    cycle = ScanCycle(ScanLocalizer(points))
    errors = []
    for k, scan in enumerate(slam_sim.drive(world, route, seed=seed)):
        start = (compose(scan.truth, OFF), np.diag([0.3, 0.3, math.radians(8)]) ** 2)
        dr = scan.dead_reckoning
        cycle.step(Scan(float(k), scan.ranges, ANGLES, LaserGeometry().max_range), dr, scan.increment_covariance,
                   start=start)
        pose = cycle.method.pose
        errors.append((math.dist(pose[:2], scan.truth[:2]), abs(float(wrap(pose[2] - scan.truth[2])))))
    return np.array(errors)


def test_the_office_is_localized_from_a_start_that_is_off() -> None:
    world = load_map(f'{MAPS}/office.xml')
    errors = _localize(world, wall_points(world.walls), 2, 20.0)
    assert len(errors) > 80
    settled = errors[10:]
    assert np.sqrt(np.mean(settled[:, 0] ** 2)) < 0.05 and settled[:, 0].max() < 0.1
    assert np.sqrt(np.mean(settled[:, 1] ** 2)) < math.radians(1.0)


def test_a_generated_map_as_an_occupancy_grid() -> None:
    world = random_maps.random_map(9)
    # The grid a robot would have made: scans from the truth along another route.
    scans = list(slam_sim.drive(world, slam_sim.loop_route(world, 10.0, np.random.default_rng(1)), seed=1))
    grid = build_grid([s.truth for s in scans], [(ANGLES, s.ranges) for s in scans], resolution=0.05)
    errors = _localize(world, grid.occupied_points, 4, 10.0)
    settled = errors[10:]
    assert np.sqrt(np.mean(settled[:, 0] ** 2)) < 0.05 and settled[:, 0].max() < 0.12
