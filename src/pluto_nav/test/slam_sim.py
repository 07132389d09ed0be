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
from collections.abc import Iterator

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
from pluto_nav.pose_filter import PoseFilter
from pluto_nav.slam_filter import LINE_EXTRACTION, SlamFilter, SlamSettings, SlamUpdate
from pluto_nav.wall_map import WallMap

__all__ = ['Scan', 'SlamRun', 'drive', 'localize', 'loop_route', 'place_route', 'run',
           'wall_errors', 'wall_errors_same_wall']


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
    updates: list                  # SlamUpdate of each scan
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


@dataclasses.dataclass(frozen=True)
class Scan:
    """What one scan period gives an estimator, and the truth to score it."""

    increment: np.ndarray          # odometry increment of the laser since the last scan
    increment_covariance: np.ndarray
    lines: list                    # lines of the noisy scan (laser frame)
    truth: np.ndarray              # true laser pose
    dead_reckoning: np.ndarray     # laser pose from odometry alone
    distance: float                # m driven (odometry's count)
    ranges: np.ndarray | None = None   # the noisy scan itself (m, robot order, -90 to +90 degrees)
    odometry: tuple = (0.0, 0.0, 0.0)  # the base's odometry reading at the scan


def drive(world: World, route: np.ndarray, *, seed: int, length_m: float = math.inf,
          noise: OdometryNoise = NOISE, extraction: dict | None = None) -> Iterator[Scan]:
    """Drive ``route`` from the place ``start`` (up to ``length_m`` metres); one :class:`Scan`
    per scan period, the first taken standing at the start (zero increment).

    :param extraction: keyword arguments for ``extract_lines`` (None: its defaults).
    :raises RuntimeError: if the robot bumps into a wall (a route too close to one).
    """
    rng = np.random.default_rng(seed)
    start = world.place('start')
    robot = SimRobot(world, RobotSpec(odometry_noise=noise), rng, start=tuple(start))
    geometry = LaserGeometry(mount_x=MOUNT[0], noise_sigma=LASER_SIGMA)
    laser = LaserModel(geometry, rng)
    range_sigma = math.hypot(LASER_SIGMA, geometry.resolution / math.sqrt(12.0))
    model = OdometryNoiseModel(trans=noise.trans, rot=noise.rot, drift=noise.drift)

    def scan(increment: np.ndarray, covariance: np.ndarray, odo: tuple) -> Scan:
        t = robot.truth
        ranges = laser.scan(world, t.x, t.y, t.theta)
        lines = extract_lines(ranges, range_sigma=range_sigma, max_range=geometry.max_range,
                              **(extraction or {}))
        return Scan(increment, covariance, lines, compose((t.x, t.y, t.theta), MOUNT),
                    compose(compose(tuple(start), odo), MOUNT), robot.distance, np.asarray(ranges), odo)

    last_odo = (0.0, 0.0, 0.0)
    yield scan(np.zeros(3), np.zeros((3, 3)), last_odo)
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
            raise RuntimeError(f'{world.name}: the robot bumped into a wall at {robot.truth}')
        if step % SCAN_STEPS:
            continue
        odo = (robot.odometry.x, robot.odometry.y, robot.odometry.theta)
        u_robot = relative(last_odo, odo)
        last_odo = odo
        yield scan(*laser_increment(u_robot, increment_covariance(u_robot, model), MOUNT), odo)


def run(world: World, route: np.ndarray, *, seed: int, length_m: float = math.inf,
        settings: SlamSettings = SlamSettings(), noise: OdometryNoise = NOISE,
        check_every: int = 0, extraction: dict | None = LINE_EXTRACTION) -> SlamRun:
    """SLAM along ``route`` (see :func:`drive`), starting at the true laser pose, exactly known;
    lines extracted with ``extraction`` (:data:`pluto_nav.slam_filter.LINE_EXTRACTION`).

    :param check_every: every this many scans after the first, check that the full covariance
        is positive definite (0: never).
    """
    slam = SlamFilter(settings=settings)
    rows: list[tuple] = []
    updates: list[SlamUpdate] = []
    spd = True
    for k, scan in enumerate(drive(world, route, seed=seed, length_m=length_m, noise=noise,
                                   extraction=extraction)):
        if k == 0:
            slam.set_pose(scan.truth, np.zeros((3, 3)))
        began = time.process_time()
        if k > 0:
            slam.predict(scan.increment, scan.increment_covariance)
        updates.append(slam.update(scan.lines))
        spent = time.process_time() - began
        est = slam.pose
        dead = scan.dead_reckoning
        rows.append((scan.distance, math.dist(est[:2], scan.truth[:2]),
                     abs(wrap(est[2] - scan.truth[2])), math.dist(dead[:2], scan.truth[:2]),
                     abs(wrap(dead[2] - scan.truth[2])), spent, len(slam)))
        if check_every and k % check_every == 0 and k > 0:     # at k = 0 the pose is exact
            spd &= bool(np.linalg.eigvalsh(slam.state()[1])[0] > 0.0)
    data = np.array(rows).reshape(-1, 7)
    return SlamRun(world.name, *data.T, filter=slam, world=world, updates=updates, spd=spd)


def localize(world: World, walls: np.ndarray, start: tuple[float, float, float],
             route: np.ndarray, *, seed: int, length_m: float = math.inf) -> np.ndarray:
    """Drive ``route`` in ``world`` with a PoseFilter on the map ``walls`` from the robot pose
    ``start`` (the map's place); the filter's position error (m) at each scan."""
    filt = PoseFilter()
    wall_map = WallMap(walls)
    errors = []
    for k, scan in enumerate(drive(world, route, seed=seed, length_m=length_m)):
        if k == 0:
            filt.set_pose(compose(start, MOUNT), np.diag([1e-4, 1e-4, 1e-4]))
        else:
            filt.predict(scan.increment, scan.increment_covariance)
        filt.update(scan.lines, wall_map)
        errors.append(math.dist(filt.pose[:2], scan.truth[:2]))
    return np.array(errors)


def wall_errors(walls: np.ndarray, world: World, *, step: float = 0.05) -> np.ndarray:
    """For each mapped wall, the largest distance (m) of any of its points (endpoints included,
    and every ``step`` between) from the nearest true wall.

    So a wall is good when it lies along true walls end to end: an end that overshoots a corner,
    a wall drawn across a door gap or a wall off to the side all count; a wall drawn over two
    pieces of true wall that touch (a wall in two pieces, a few centimetres out of line, which
    the line extractor cannot tell apart) does not.
    """
    truth = np.asarray(world.walls, dtype=float).reshape(-1, 4)
    a, d = truth[:, 0:2], truth[:, 2:4] - truth[:, 0:2]
    length2 = np.einsum('ij,ij->i', d, d)
    out = np.empty(len(walls))
    for i, wall in enumerate(np.asarray(walls).reshape(-1, 4)):
        count = max(2, int(math.ceil(math.dist(wall[:2], wall[2:]) / step)) + 1)
        points = wall[:2] + np.linspace(0.0, 1.0, count)[:, None] * (wall[2:] - wall[:2])
        rel = points[:, None, :] - a[None, :, :]                              # (P, W, 2)
        u = np.clip(np.einsum('pwj,wj->pw', rel, d) / length2, 0.0, 1.0)
        gap = rel - u[..., None] * d[None, :, :]
        out[i] = float(np.sqrt(np.einsum('pwj,pwj->pw', gap, gap).min(axis=1)).max())
    return out


def wall_errors_same_wall(walls: np.ndarray, world: World) -> np.ndarray:
    """For each mapped wall, how far (m) its farther endpoint lies from one true wall, the same
    for both ends (with its chain: collinear walls that touch, ``WallMap.chain_extent``)."""
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
