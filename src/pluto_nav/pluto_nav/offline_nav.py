"""``offline_nav``: a real robot's recording through Pluto's SLAM or localization, without ROS.

    offline_nav LOG --slam [--trajectory OUT.tum] [--map-out MAP.xml] [options]
    offline_nav LOG --localize MAP [--trajectory OUT.tum] [options]

``LOG`` is a CARMEN log (plain or gzip) or a rosbag2 bag (its directory, metadata.yaml, or one
.mcap/.db3 file).  The estimation is the slamModule's or poseModule's own code
(:mod:`.slam_methods`, :mod:`.localizers`, run by :mod:`.offline_run` as the modules run it), over
the whole log as fast as one core allows, the same every time.  docs/real-data.md ("Offline runs") gives
the outputs and the scoring; docs/pluto-nav.md ("offline_nav") the start pose, the IMU option and
the exit status.

Prints progress (a bar on a terminal) and a summary; problems with the log are warned once per
kind and counted in the summary.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from wurde_idl.errors import ConfigError
from wurde_idl.gridmap import save_grid_map
from wurde_idl.mapfile import MapData, save_map_data
from wurde_idl.maps import load_any_map

from .estimator import Estimator
from .localizers import LineLocalizer, ScanLocalizer, wall_points
from .logs import LogError, RobotLog, load_log
from .occupancy import OCCUPIED, Grid, build_grid
from .offline_run import OfflineResult, run_offline
from .slam_methods import METHODS as SLAM_METHODS
from .slam_metric import MetricError, load_relations, load_trajectory, relation_error, relative_pose_error, save_tum
from .wall_map import WallMap

if TYPE_CHECKING:
    from rich.progress import Progress, TaskID

__all__ = ['main']


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog='offline_nav', description=__doc__.split('\n\n')[0])
    parser.add_argument('log', help='a CARMEN log (.clf, .log, gzip too) or a rosbag2 bag')
    task = parser.add_mutually_exclusive_group(required=True)
    task.add_argument('--slam', action='store_true', help="the slamModule's SLAM")
    task.add_argument('--localize', metavar='MAP',
                      help="the poseModule's localization in MAP (XML, map_server YAML or CARMEN map)")
    parser.add_argument('--method', choices=('scans', 'lines'), default='scans',
                        help='scans (default): scan matching; lines: line features (Pluto 7)')
    parser.add_argument('--trajectory', metavar='OUT.tum', help='write the trajectory (TUM format)')
    parser.add_argument('--map-out', metavar='MAP.xml', help='SLAM: write the map (and MAP.yaml + MAP.pgm)')
    parser.add_argument('--laser', help='which laser: front, rear, raw1..4 or a bag topic (default: the front one)')
    parser.add_argument('--start', metavar='X,Y,THETA', help="localization: the start pose (default: the map's start)")
    parser.add_argument('--relations', metavar='FILE', help='score against ground-truth relations (Kuemmerle et al.)')
    parser.add_argument('--reference', metavar='FILE', help='score against a reference trajectory (TUM or graph log)')
    parser.add_argument('--no-imu', action='store_true',
                        help="the heading from the odometry alone, not from the log's IMU (a bag's sensor_msgs/Imu)")
    parser.add_argument('--quiet', action='store_true', help='no progress, only the summary')
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``offline_nav`` (see the module's description and docs/pluto-nav.md).

    :param argv: the arguments without the program's name; None: ``sys.argv[1:]``.
    :returns: the exit status: 0, 1 when the run failed, 2 for wrong arguments or an unreadable
        log or map.
    """
    args = _parser().parse_args(list(sys.argv[1:] if argv is None else argv))
    say = _Say(quiet=args.quiet)
    try:
        log = load_log(args.log, laser=args.laser, warn=say.warn)
        if not log.scans:
            raise LogError(f'{args.log}: no laser scans to use ({log.problems.summary()})')
        if args.slam:
            method = SLAM_METHODS[args.method]()
            start, covariance = None, None
        else:
            method, start, covariance = _localizer(args.localize, args.method, args.start)
        relations = load_relations(args.relations) if args.relations else None
        reference = load_trajectory(args.reference) if args.reference else None
    except (LogError, ConfigError, MetricError) as error:
        print(f'offline_nav: {error}', file=sys.stderr)
        return 2
    heading = [r for r in log.imu if r.orientation is not None]
    imu = f', {len(heading)} IMU headings{" (not used)" if args.no_imu else ""}' if heading else ''
    say.line(f'offline_nav: {log.path}: {len(log.scans)} scans ({_beams(log)}), {len(log.odometry)} odometry '
             f'from {log.odometry_source}{imu}, {log.duration:.0f} s; {"SLAM" if args.slam else "localization"}, '
             f'method {args.method}')
    try:
        with say.progress(len(log.scans)) as progress:
            result = run_offline(log, method, start=start, start_covariance=covariance, imu=not args.no_imu,
                                 progress=progress)
    except ValueError as error:
        print(f'offline_nav: {error}', file=sys.stderr)
        return 1
    written = _write(args, log, method, result)
    _summary(say, log, result, written, method)
    if relations is not None:
        say.line(f'relations ({args.relations}):')
        say.line(f'  ours:     {relation_error(result.stamps, result.robot, relations).line()}')
        say.line(f'  odometry: {relation_error(result.stamps, result.odometry, relations).line()}')
    if reference is not None:
        say.line(f'relative pose error against {args.reference} (pairs 0.3-2 m apart):')
        say.line(f'  ours:     {relative_pose_error(result.stamps, result.robot, *reference).line()}')
        say.line(f'  odometry: {relative_pose_error(result.stamps, result.odometry, *reference).line()}')
    return 0 if len(result.stamps) else 1


def _beams(log: RobotLog) -> str:
    first = log.scans[0]
    span = np.degrees(first.config.angular_resolution * (len(first.ranges) - 1))
    return f'{len(first.ranges)} beams over {span:.0f} deg'


def _localizer(path: str, method: str, start_text: str | None
               ) -> tuple[LineLocalizer | ScanLocalizer, tuple[float, float, float], np.ndarray]:
    """The localizer, the robot's start pose and the laser's start covariance for ``--localize``."""
    walls, points, places = _load_map(path)
    localizer = LineLocalizer(WallMap(walls)) if method == 'lines' else ScanLocalizer(points)
    if start_text is not None:
        try:
            start = tuple(float(v) for v in start_text.split(','))
        except ValueError:
            start = ()
        if len(start) != 3:
            raise ConfigError('--start', None, f'{start_text!r} is not X,Y,THETA')
    elif 'start' in places:
        start = places['start']
    else:
        raise ConfigError(path, None, 'the map has no place "start": give --start X,Y,THETA')
    return localizer, start, np.diag(np.square(Estimator.START_SIGMA))


def _load_map(path: str) -> tuple[np.ndarray, np.ndarray, dict[str, tuple[float, float, float]]]:
    """Walls, points and places of any map (:func:`wurde_idl.maps.load_any_map`, chosen by
    content): a grid's points are its occupied cells' centres, a wall map's points along its walls."""
    loaded = load_any_map(path)
    walls = np.asarray(loaded.data.walls, dtype=float).reshape(-1, 4)
    places = {k: (v.x, v.y, v.theta) for k, v in loaded.data.places.items()}
    if loaded.grid is None:
        if not len(walls):
            raise ConfigError(path, None, 'the map has no walls to localize against')
        return walls, wall_points(walls), places
    grid = loaded.grid
    found = Grid(grid.cells, grid.origin[:2], grid.resolution)
    if not (grid.cells == OCCUPIED).any():
        raise ConfigError(path, None, 'the map has no occupied cells to localize against')
    return walls, found.occupied_points, places


def _write(args: argparse.Namespace, log: RobotLog, method: object, result: OfflineResult) -> list[str]:
    written = []
    if args.trajectory:
        save_tum(args.trajectory, result.stamps, result.robot)
        written.append(args.trajectory)
    if args.map_out and args.slam:
        target = pathlib.Path(args.map_out)
        mount = log.scans[0].config.mount
        data: MapData = method.map_data(f'offline-{pathlib.Path(log.path).name}', mount=mount)  # type: ignore[attr-defined]
        grid = method.grid() or _grid(log, result)  # type: ignore[attr-defined]
        target.parent.mkdir(parents=True, exist_ok=True)
        save_map_data(data, target)
        save_grid_map(target.with_suffix('.yaml'), grid.cells, origin=grid.origin, resolution=grid.resolution)
        written += [str(target), str(target.with_suffix('.yaml')), str(target.with_suffix('.pgm'))]
    return written


def _grid(log: RobotLog, result: OfflineResult) -> Grid:
    """An occupancy grid of the scans at the trajectory's laser poses (for methods without one)."""
    by_stamp = {scan.stamp: scan for scan in log.scans}
    rays = [(by_stamp[t].angles, by_stamp[t].ranges) for t in result.stamps]
    return build_grid(result.laser, rays)


def _summary(say: _Say, log: RobotLog, result: OfflineResult, written: list[str], method: object) -> None:
    used = len(result.stamps)
    rate = log.duration / result.seconds if result.seconds > 0 else float('inf')
    say.line(f'scans used {used} of {len(log.scans)} ({result.matched} matched, {result.skipped} skipped); '
             f'{result.seconds:.1f} s for {log.duration:.0f} s of log ({rate:.1f}x its pace)')
    slam = getattr(method, 'slam', None)
    if slam is not None:
        say.line(f'graph: {len(slam)} nodes, {slam.closures} loop closures')
    if len(result.odometry) > 1:
        driven = float(np.sum(np.hypot(*np.diff(result.odometry[:, :2], axis=0).T)))
        say.line(f'driven {driven:.1f} m by odometry')
    say.line(f'log problems: {log.problems.summary()}')
    for path in written:
        say.line(f'wrote {path}')


class _Say:
    """Messages to standard output, warnings to standard error, and the progress display."""

    def __init__(self, *, quiet: bool) -> None:
        self.quiet = quiet

    def line(self, text: str) -> None:
        print(text, flush=True)

    def warn(self, text: str) -> None:
        print(f'offline_nav: warning: {text}', file=sys.stderr, flush=True)

    def progress(self, total: int) -> _Progress:
        return _Progress(total, quiet=self.quiet)


class _Progress:
    """A rich progress bar on a terminal, a line every tenth otherwise (nothing when quiet)."""

    def __init__(self, total: int, *, quiet: bool) -> None:
        self.total, self.quiet = total, quiet
        self.bar: Progress | None = None
        self.task: TaskID | None = None
        self.shown = -1
        self.begun = time.perf_counter()

    def __enter__(self) -> Callable[[int, int], None]:
        if not self.quiet and sys.stderr.isatty():
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
            self.bar = Progress(TextColumn('scans'), BarColumn(), TextColumn('{task.completed}/{task.total}'),
                                TimeElapsedColumn(), TimeRemainingColumn(), transient=True)
            self.bar.start()
            self.task = self.bar.add_task('scans', total=self.total)
        return self.update

    def update(self, done: int, total: int) -> None:
        if self.quiet:
            return
        if self.bar is not None:
            assert self.task is not None  # added with the bar
            self.bar.update(self.task, completed=done)
            return
        tenth = (10 * done) // max(1, total)
        if tenth != self.shown:
            self.shown = tenth
            print(f'  {done}/{total} scans, {time.perf_counter() - self.begun:.1f} s', file=sys.stderr, flush=True)

    def __exit__(self, *exc: object) -> None:
        if self.bar is not None:
            self.bar.stop()


if __name__ == '__main__':
    sys.exit(main())
