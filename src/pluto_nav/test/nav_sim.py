"""Offline localization runs in the simulator, no ROS: drive a route, feed the PoseFilter.

Used by ``test_nav_offline.py`` (short runs) and ``bench/nav_offline.py`` (long runs).  The robot
(``wurde_drivers.sim.SimRobot``) follows a route planned on the map's occupancy grid, steering by
its *true* pose so the route is driven whatever the filter does.  Each scan period the filter
predicts with the odometry increment of the laser since the last scan (with the covariance of
``pluto_nav.odometry_model``) and updates with the lines of the noisy simulated scan.  Errors are
the filter's laser pose, and the dead-reckoned laser pose (odometry alone), against the truth.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra
from wurde_drivers.sim.grid import OccupancyGrid
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.robot import OdometryNoise, RobotSpec, SimRobot
from wurde_drivers.sim.world import World

from pluto_nav.geometry import compose, relative, wrap
from pluto_nav.lines import extract_lines
from pluto_nav.odometry_model import OdometryNoiseModel, increment_covariance, laser_increment
from pluto_nav.pose_filter import PoseFilter
from pluto_nav.wall_map import WallMap

__all__ = ['RunResult', 'plan_route', 'run']

MOUNT = (0.2, 0.0, 0.0)
NOISE = OdometryNoise(trans=0.05, rot=0.05, drift=0.02)
LASER_SIGMA = 0.01
DT = 0.05                  # s, simulator step
SCAN_STEPS = 4             # a scan every 0.2 s (a 361-beam SICK at 38400 baud: 0.19 s)
SPEED = 0.5                # m/s cruising
CLEARANCE = 0.6            # m from walls for the route (the robot's radius is 0.35)
GRID = 0.1                 # m, planning grid


@dataclasses.dataclass
class RunResult:
    """Errors of one run: one row for the start, then one per scan (after its update)."""

    name: str
    distance: np.ndarray           # m driven at each scan (the base's odometer)
    error_xy: np.ndarray           # m, filter vs truth
    error_theta: np.ndarray        # rad
    odo_xy: np.ndarray             # m, dead reckoning vs truth
    odo_theta: np.ndarray
    matches: np.ndarray            # lines used per scan
    nis: np.ndarray                # NIS per dof (NaN when no update)
    bumped: bool = False

    @property
    def driven(self) -> float:
        return float(self.distance[-1]) if len(self.distance) else 0.0

    def rmse(self, start_m: float = 0.0) -> tuple[float, float, float, float]:
        """RMSE of position (m) and heading (rad), filter then odometry, from ``start_m`` on."""
        keep = self.distance >= start_m
        return tuple(float(np.sqrt(np.mean(a[keep] ** 2)))
                     for a in (self.error_xy, self.error_theta, self.odo_xy, self.odo_theta))

    def recovered_after(self, limit_m: float) -> float:
        """Metres driven until the position error falls below ``limit_m`` for good (inf: never)."""
        above = np.flatnonzero(self.error_xy >= limit_m)
        if len(above) == 0:
            return 0.0
        if above[-1] == len(self.error_xy) - 1:
            return math.inf
        return float(self.distance[above[-1] + 1])


def plan_route(world: World, start: tuple[float, float], length_m: float,
               rng: np.random.Generator) -> np.ndarray:
    """A path ``(K, 2)`` from ``start`` through random reachable goals, ``length_m`` or longer,
    keeping ``CLEARANCE`` from walls and preferring the middle of free space."""
    grid = OccupancyGrid.from_world(world, GRID, offlimits=True)
    clearance = ndimage.distance_transform_edt(grid.data < 0.5) * GRID
    ix, iy = grid.cells(np.array([start]))
    labels, _ = ndimage.label(clearance >= CLEARANCE, structure=np.ones((3, 3)))
    region = labels == labels[iy[0], ix[0]]
    if labels[iy[0], ix[0]] == 0:
        raise ValueError(f'start {start} of {world.name} is not {CLEARANCE} m clear')
    graph, cells = _grid_graph(region, clearance)
    node = {int(c): k for k, c in enumerate(cells)}
    here = node[int(iy[0] * region.shape[1] + ix[0])]
    path = [np.asarray(start, dtype=float)]
    total = 0.0
    while total < length_m:
        far = rng.choice(len(cells), 12, replace=False)
        dist, pred = dijkstra(graph, indices=here, return_predecessors=True)
        goal = int(far[np.argmax(np.where(np.isfinite(dist[far]), dist[far], -1))])
        steps = [goal]
        while steps[-1] != here:
            steps.append(int(pred[steps[-1]]))
        flat = cells[steps[::-1]]
        xy = grid.centers(flat % region.shape[1], flat // region.shape[1])
        xy = xy[::3] if len(xy) > 3 else xy
        total += float(np.sum(np.hypot(*np.diff(np.vstack([path[-1], xy]), axis=0).T)))
        path.extend(xy)
        here = goal
    return np.array(path)


def _grid_graph(region: np.ndarray, clearance: np.ndarray):
    """8-connected graph of the cells of ``region``; a step costs its length, more near walls."""
    height, width = region.shape
    cells = np.flatnonzero(region.reshape(-1))
    index = -np.ones(height * width, dtype=np.int64)
    index[cells] = np.arange(len(cells))
    rows, cols, costs = [], [], []
    cy, cx = cells // width, cells % width
    penalty = 1.0 + 1.0 / np.maximum(clearance.reshape(-1)[cells], 0.1)
    for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
        ny, nx = cy + dy, cx + dx
        ok = (ny < height) & (nx >= 0) & (nx < width)
        target = index[np.where(ok, ny * width + nx, 0)]
        ok &= target >= 0
        step = math.hypot(dx, dy) * penalty[ok]
        rows += [np.arange(len(cells))[ok], target[ok]]
        cols += [target[ok], np.arange(len(cells))[ok]]
        costs += [step, step]
    graph = coo_matrix((np.concatenate(costs), (np.concatenate(rows), np.concatenate(cols))),
                       shape=(len(cells), len(cells))).tocsr()
    return graph, cells


def run(world: World, *, length_m: float, seed: int, offset: tuple[float, float, float] = (0, 0, 0),
        start_sigma: tuple[float, float] = (0.02, math.radians(1.0)),
        noise: OdometryNoise = NOISE, record: list | None = None) -> RunResult:
    """Drive ``length_m`` metres from the place ``start`` and localize with a PoseFilter.

    :param offset: the filter starts at the true laser pose composed with this (x, y, theta).
    :param start_sigma: standard deviations (m, rad) of the filter's initial covariance.
    :param record: if given, gets ``(increment, covariance, lines)`` of every scan appended (what
        the filter was fed, for replaying it).
    """
    rng = np.random.default_rng(seed)
    start = world.place('start')
    route = plan_route(world, (start.x, start.y), 1.2 * length_m + 5.0, rng)
    robot = SimRobot(world, RobotSpec(odometry_noise=noise), rng, start=tuple(start))
    geometry = LaserGeometry(mount_x=MOUNT[0], noise_sigma=LASER_SIGMA)
    laser = LaserModel(geometry, rng)
    range_sigma = math.hypot(LASER_SIGMA, geometry.resolution / math.sqrt(12.0))
    wall_map = WallMap(world.walls)
    model = OdometryNoiseModel(trans=noise.trans, rot=noise.rot, drift=noise.drift)
    truth_laser = compose(tuple(start), MOUNT)
    filt = PoseFilter()
    sxy, sth = start_sigma
    filt.set_pose(compose(truth_laser, offset), np.diag([sxy ** 2, sxy ** 2, sth ** 2]))
    last_odo = (0.0, 0.0, 0.0)
    est = filt.pose                                     # the first row: where the filter starts
    rows: list[tuple] = [(0.0, math.dist(est[:2], truth_laser[:2]),
                          abs(wrap(est[2] - truth_laser[2])), 0.0, 0.0, 0, math.nan)]
    target, step = 1, 0
    max_steps = int(10 * length_m / (SPEED * DT))
    while robot.distance < length_m and step < max_steps:
        target = _steer(robot, route, target)
        if target < 0:
            break                                      # the end of the route
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
        filt.predict(u_laser, q_laser)
        t = robot.truth
        lines = extract_lines(laser.scan(world, t.x, t.y, t.theta), range_sigma=range_sigma,
                              max_range=geometry.max_range)
        result = filt.update(lines, wall_map)
        if record is not None:
            record.append((u_laser, q_laser, lines))
        true_laser = compose((t.x, t.y, t.theta), MOUNT)
        dead = compose(compose(tuple(start), odo), MOUNT)
        est = filt.pose
        rows.append((robot.distance, math.dist(est[:2], true_laser[:2]),
                     abs(wrap(est[2] - true_laser[2])), math.dist(dead[:2], true_laser[:2]),
                     abs(wrap(dead[2] - true_laser[2])), result.matches, result.nis))
    data = np.array(rows).reshape(-1, 7)
    return RunResult(world.name, *data.T, bumped=robot.bumper_stop)


def _steer(robot: SimRobot, route: np.ndarray, target: int) -> int:
    """Pure pursuit on the true pose: command the robot toward the route; the next target
    (-1 at the end of the route)."""
    t = robot.truth
    while math.dist((t.x, t.y), route[target]) < 0.35:
        if target == len(route) - 1:
            robot.stop()
            return -1
        target += 1
    gx, gy = route[target]
    error = wrap(math.atan2(gy - t.y, gx - t.x) - t.theta)
    tv = SPEED * max(0.0, math.cos(error)) ** 2 if abs(error) < 0.6 else 0.0
    robot.command(tv, max(-1.0, min(1.0, 2.0 * error)))
    return target
