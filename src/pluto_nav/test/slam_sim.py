"""Offline SLAM runs in the simulator, no ROS: drive a loop, feed the SlamFilter, score it.

Used by ``test_slam_filter.py`` (short runs) and ``bench/slam_offline.py`` (long loops).  The
robot, laser, noise, scan rate and steering are ``nav_sim``'s (odometry noise trans 0.05, rot 0.05,
drift 0.02; laser noise 0.01 m; a scan every 0.2 s; pure pursuit on the true pose).  The filter
starts at the true laser pose with zero covariance, so its map frame is the world's and the map
can be compared with the world's walls directly.  A route is a list of waypoints; ``loop_route``
plans random goals and then the way back to the start, so every run closes a loop.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from scipy import ndimage
from scipy.sparse.csgraph import dijkstra
from wurde_drivers.sim.grid import OccupancyGrid
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.robot import OdometryNoise, RobotSpec, SimRobot
from wurde_drivers.sim.world import World

from nav_sim import CLEARANCE, DT, GRID, LASER_SIGMA, MOUNT, NOISE, SCAN_STEPS, SPEED, \
    _grid_graph, _steer, plan_route
from pluto_nav.geometry import compose, relative, wrap
from pluto_nav.lines import extract_lines
from pluto_nav.odometry_model import OdometryNoiseModel, increment_covariance, laser_increment
from pluto_nav.slam_filter import SlamFilter, SlamSettings
from pluto_nav.wall_map import WallMap

__all__ = ['SlamRun', 'loop_route', 'place_route', 'run', 'wall_errors']


@dataclasses.dataclass
class SlamRun:
    """One run: a row per scan, and the filter at the end."""

    name: str
    distance: np.ndarray           # m driven (odometry's count) at each scan
    error_xy: np.ndarray           # m, filter vs truth (laser pose)
    error_theta: np.ndarray        # rad
    odo_xy: np.ndarray             # m, dead reckoning vs truth
    odo_theta: np.ndarray
    update_s: np.ndarray           # s of CPU per predict + update
    landmarks: np.ndarray          # landmarks after each update
    filter: SlamFilter
    world: World
    bumped: bool = False
    spd: bool = True               # every sampled full covariance was positive definite

    @property
    def driven(self) -> float:
        return float(self.distance[-1]) if len(self.distance) else 0.0

    def rmse(self) -> tuple[float, float, float, float]:
        """RMSE of position (m) and heading (rad), filter then odometry."""
        return tuple(float(np.sqrt(np.mean(a ** 2)))
                     for a in (self.error_xy, self.error_theta, self.odo_xy, self.odo_theta))


def place_route(world: World, names: list[str]) -> np.ndarray:
    """Waypoints ``(K, 2)``: the named places, in order (straight legs between them)."""
    return np.array([world.place(name)[:2] for name in names], dtype=float)


def loop_route(world: World, length_m: float, rng: np.random.Generator) -> np.ndarray:
    """Random goals for ``length_m`` metres (``nav_sim.plan_route``), then back to ``start``."""
    start = world.place('start')
    out = plan_route(world, (start.x, start.y), length_m, rng)
    grid = OccupancyGrid.from_world(world, GRID, offlimits=True)
    clearance = ndimage.distance_transform_edt(grid.data < 0.5) * GRID
    labels, _ = ndimage.label(clearance >= CLEARANCE, structure=np.ones((3, 3)))
    ix, iy = grid.cells(np.array([[start.x, start.y], out[-1]]))
    region = labels == labels[iy[0], ix[0]]
    graph, cells = _grid_graph(region, clearance)
    node = {int(c): k for k, c in enumerate(cells)}
    home = node[int(iy[0] * region.shape[1] + ix[0])]
    here = node[int(iy[1] * region.shape[1] + ix[1])]
    _, pred = dijkstra(graph, indices=home, return_predecessors=True)
    steps = [here]
    while steps[-1] != home:
        steps.append(int(pred[steps[-1]]))
    back = grid.centers(cells[steps] % region.shape[1], cells[steps] // region.shape[1])
    back = back[::3] if len(back) > 3 else back
    return np.vstack([out, back, [[start.x, start.y]]])


def run(world: World, route: np.ndarray, *, seed: int, length_m: float = math.inf,
        settings: SlamSettings = SlamSettings(), noise: OdometryNoise = NOISE,
        check_every: int = 0) -> SlamRun:
    """Drive ``route`` from the place ``start`` (up to ``length_m`` metres) doing SLAM.

    :param check_every: every this many scans, check the full covariance is SPD (0: never).
    """
    rng = np.random.default_rng(seed)
    start = world.place('start')
    robot = SimRobot(world, RobotSpec(odometry_noise=noise), rng, start=tuple(start))
    geometry = LaserGeometry(mount_x=MOUNT[0], noise_sigma=LASER_SIGMA)
    laser = LaserModel(geometry, rng)
    range_sigma = math.hypot(LASER_SIGMA, geometry.resolution / math.sqrt(12.0))
    model = OdometryNoiseModel(trans=noise.trans, rot=noise.rot, drift=noise.drift)
    slam = SlamFilter(settings=settings)
    slam.set_pose(compose(tuple(start), MOUNT), np.zeros((3, 3)))
    # SLAM starts with the robot standing at the start: the first map comes from there.
    slam.update(extract_lines(laser.scan(world, *start), range_sigma=range_sigma,
                              max_range=geometry.max_range))
    last_odo = (0.0, 0.0, 0.0)
    rows: list[tuple] = []
    spd = True
    target, step = 1, 0
    route_length = float(np.sum(np.hypot(*np.diff(route, axis=0).T)))
    max_steps = int(3 * min(length_m, route_length + 10.0) / (SPEED * DT)) + 1000
    while robot.distance < length_m and step < max_steps:
        target = _steer(robot, route, target)
        if target < 0:
            break
        robot.step(DT)
        step += 1
        if robot.bumper_stop:
            break
        if step % SCAN_STEPS:
            continue
        odo = (robot.odometry.x, robot.odometry.y, robot.odometry.theta)
        u_robot = relative(last_odo, odo)
        u_laser, q_laser = laser_increment(u_robot, increment_covariance(u_robot, model), MOUNT)
        last_odo = odo
        t = robot.truth
        lines = extract_lines(laser.scan(world, t.x, t.y, t.theta), range_sigma=range_sigma,
                              max_range=geometry.max_range)
        began = time.process_time()
        slam.predict(u_laser, q_laser)
        slam.update(lines)
        spent = time.process_time() - began
        true_laser = compose((t.x, t.y, t.theta), MOUNT)
        dead = compose(compose(tuple(start), odo), MOUNT)
        est = slam.pose
        rows.append((robot.distance, math.dist(est[:2], true_laser[:2]),
                     abs(wrap(est[2] - true_laser[2])), math.dist(dead[:2], true_laser[:2]),
                     abs(wrap(dead[2] - true_laser[2])), spent, len(slam)))
        if check_every and len(rows) % check_every == 0:
            spd &= bool(np.linalg.eigvalsh(slam.state_covariance())[0] > 0.0)
    data = np.array(rows).reshape(-1, 7)
    return SlamRun(world.name, *data.T, filter=slam, world=world, bumped=robot.bumper_stop,
                   spd=spd)


def wall_errors(walls: np.ndarray, world: World) -> np.ndarray:
    """For each mapped wall, how far (m) its farther endpoint lies from the nearest true wall.

    A true wall counts with its chain (collinear walls that touch, ``WallMap.chain_extent``), so
    a mapped wall along an outer wall drawn in two pieces is scored against the whole of it.
    """
    truth = WallMap(world.walls)
    normal = np.column_stack([np.cos(truth.gamma), np.sin(truth.gamma)])
    along_dir = np.column_stack([-normal[:, 1], normal[:, 0]])
    out = np.empty(len(walls))
    for i, wall in enumerate(np.asarray(walls).reshape(-1, 4)):
        ends = wall.reshape(2, 2)
        off = ends @ normal.T - truth.rho                            # (2, W)
        t = ends @ along_dir.T                                       # (2, W)
        outside = np.maximum(0.0, np.maximum(truth.chain_extent[:, 0] - t,
                                             t - truth.chain_extent[:, 1]))
        out[i] = float(np.min(np.max(np.hypot(off, outside), axis=0)))
    return out
