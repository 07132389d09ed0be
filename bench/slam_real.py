"""Benchmark: Pluto's SLAM on real robots' logs, scored by the public SLAM benchmark's metric.

Kümmerle et al., "On measuring the accuracy of SLAM algorithms" (Autonomous Robots 27(4), 2009):
the relation metric (mean absolute translational and rotational error of the displacement between
pairs of scans) on Freiburg 079 against its ground-truth relations, and relative pose error against
the reference trajectory of MIT CSAIL (pairs of scans 0.3-2 m apart), each beside odometry alone and
the published GMapping figure.  The SLAM is the slamModule's own (``offline_nav --slam``, method
``scans`` and, for comparison, Pluto's ``lines``), run on one core (this process is pinned to one
CPU, its maths libraries to one thread).  Then the same on logs of the simulator with noise on, on
a shipped map and generated ones, scored with relations made from the simulator's truth as the
benchmark's are (consecutive scans, and scans of the same place visited again).

Usage: ``python bench/slam_real.py [--data DIR] [--generated 3] [--png docs/slam-csail.png]``
inside ``source env.sh`` (it reads the source trees; the logs are not in the repository: ``--data``
is where the benchmark's files are, by default ``../shared/data/slam-benchmark`` beside the
checkout).  About five minutes.
"""

from __future__ import annotations

import os

for _name in ('OMP_NUM_THREADS', 'OPENBLAS_NUM_THREADS', 'MKL_NUM_THREADS'):
    os.environ.setdefault(_name, '1')

import argparse  # noqa: E402
import math  # noqa: E402
import pathlib  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
for _path in ('src/pluto_nav', 'src/pluto_nav/test', 'src/wurde_drivers', 'src/wurde_interfaces'):
    sys.path.insert(0, str(ROOT / _path))

import numpy as np  # noqa: E402

from pluto_nav.geometry import relative  # noqa: E402
from pluto_nav.logs import LaserConfig, LogProblems, OdometryRecord, RobotLog, ScanRecord, load_log  # noqa: E402
from pluto_nav.offline_run import OfflineResult, run_offline  # noqa: E402
from pluto_nav.slam_methods import METHODS  # noqa: E402
from pluto_nav.slam_metric import (load_relations, load_trajectory, relation_error,  # noqa: E402
                                   relative_pose_error)

#: Published mean translational errors (m) of GMapping on all relations (Kümmerle et al. 2009).
GMAPPING = {'fr079': 0.061, 'mit-csail': 0.049}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--data', type=pathlib.Path, default=ROOT.parent / 'shared' / 'data' / 'slam-benchmark')
    parser.add_argument('--generated', type=int, default=3, help='generated maps [3]')
    parser.add_argument('--png', type=pathlib.Path, help="draw CSAIL's mapped walls over the reference's map here")
    parser.add_argument('--methods', default='scans,lines', help='slamModule methods [scans,lines]')
    args = parser.parse_args(argv)
    cpu = min(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {cpu})
    methods = args.methods.split(',')
    print(f'SLAM on real logs, one core (CPU {cpu}); translational error m, rotational deg (mean)')
    print(f'{"dataset":<22}{"metric":<24}{"pairs":>6}{"odometry":>17}{"method":>8}{"ours":>17}'
          f'{"GMapping":>10}{"time s":>8}{"log s":>7}')
    ok = True
    fr079, csail = args.data / 'fr079.clf.gz', args.data / 'mit-csail.clf.gz'
    if fr079.exists():
        relations = load_relations(args.data / 'fr079.relations')
        ok &= _rows('FR079', 'relations', load_log(fr079, warn=_quiet), methods, GMAPPING['fr079'],
                    lambda r, poses: relation_error(r.stamps, poses, relations), goal=0.061)
    if csail.exists():
        reference = load_trajectory(args.data / 'mit-csail-reference.graph.log.gz')
        log = load_log(csail, warn=_quiet)
        results = _rows('MIT CSAIL', 'RPE vs reference', log, methods, GMAPPING['mit-csail'],
                        lambda r, poses: relative_pose_error(r.stamps, poses, *reference))
        ok &= bool(results)
        if args.png:
            _draw(log, reference, args.png)
    if not (fr079.exists() or csail.exists()):
        print(f'(no benchmark logs in {args.data}: --data DIR)')
    for name, log, relations in _simulated(args.generated):
        ok &= _rows(name, 'relations (truth)', log, methods, None,
                    lambda r, poses, rel=relations: relation_error(r.stamps, poses, rel))
    return 0 if ok else 1


def _quiet(text: str) -> None:
    print(f'  log: {text}', file=sys.stderr)


def _rows(name: str, metric: str, log: RobotLog, methods: list[str], published: float | None, score,
          goal: float | None = None) -> bool:
    beats = True
    for method in methods:
        result = run_offline(log, METHODS[method]())
        ours = score(result, result.robot)
        odometry = score(result, result.odometry)
        gm = f'{published:.3f}' if published is not None else '-'
        print(f'{name:<22}{metric:<24}{ours.count:>6}{odometry.translation:>9.3f} {odometry.rotation_deg:>6.2f}'
              f'{method:>8}{ours.translation:>9.3f} {ours.rotation_deg:>6.2f}{gm:>10}{result.seconds:>8.1f}'
              f'{log.duration:>7.0f}', flush=True)
        if method == 'scans':
            beats &= ours.translation < odometry.translation and result.seconds < log.duration / 10
            if goal is not None:
                beats &= ours.translation <= goal
    return beats


def _simulated(count: int):
    """Logs of the simulated robot (odometry noise, 1 cm laser noise) on the office and
    ``count`` generated maps, with relations from the truth."""
    import random_maps
    import slam_sim
    from wurde_drivers.sim.mapfile import load_map
    worlds = [load_map(str(ROOT / 'config' / 'maps' / 'office.xml'))]
    worlds += [random_maps.random_map(100 + k) for k in range(count)]
    config = LaserConfig(-math.pi / 2, math.pi / 360, 81.9, mount=(0.2, 0.0, 0.0))
    for index, world in enumerate(worlds):
        route = slam_sim.loop_route(world, 60.0, np.random.default_rng(index))
        scans, odometry, truth = [], [], []
        for k, scan in enumerate(slam_sim.drive(world, route, seed=index)):
            stamp = 1000.0 + 0.2 * k
            scans.append(ScanRecord(stamp, np.where(np.isfinite(scan.ranges), scan.ranges, np.inf), config))
            odometry.append(OdometryRecord(stamp, *scan.odometry))
            truth.append(scan.truth)
        stamps = np.array([s.stamp for s in scans])
        robot = np.array([_robot(t) for t in truth])
        log = RobotLog(f'sim:{world.name}', scans, odometry, 'odometry records', [], [], {}, {'front': len(scans)},
                       LogProblems())
        yield f'sim {world.name}', log, _truth_relations(stamps, robot)


def _robot(laser: np.ndarray) -> np.ndarray:
    from pluto_nav.geometry import compose, inverse
    return compose(laser, inverse((0.2, 0.0, 0.0)))


def _truth_relations(stamps: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Relations as the benchmark makes them: every pair of consecutive scans, and pairs of scans
    of the same place (within 2 m, 30 s or more apart)."""
    rows = [(stamps[k], stamps[k + 1], *relative(poses[k], poses[k + 1])) for k in range(len(stamps) - 1)]
    for k in range(0, len(stamps), 5):
        near = np.flatnonzero((np.hypot(*(poses[:, :2] - poses[k, :2]).T) < 2.0) & (stamps - stamps[k] > 30.0))
        rows += [(stamps[k], stamps[j], *relative(poses[k], poses[j])) for j in near[::10]]
    return np.array(rows, dtype=float)[:, [0, 1, 2, 3, 4]]


def _draw(log: RobotLog, reference: tuple[np.ndarray, np.ndarray], path: pathlib.Path) -> None:
    """The reference's map (every scan at its reference pose, grey) and our SLAM's walls (red),
    ours moved onto the reference by the rigid transform that best aligns the two trajectories."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    method = METHODS['scans']()
    result: OfflineResult = run_offline(log, method)
    walls = np.asarray(method.map_data('csail').walls).reshape(-1, 4)
    ref_stamps, ref_poses = reference
    index = np.searchsorted(result.stamps, ref_stamps).clip(0, len(result.stamps) - 1)
    same = np.abs(result.stamps[index] - ref_stamps) < 1e-3
    ours, theirs = result.laser[index[same], :2], ref_poses[same, :2]
    mo, mt = ours.mean(axis=0), theirs.mean(axis=0)
    u, _, vt = np.linalg.svd((ours - mo).T @ (theirs - mt))
    rotation = (u @ vt).T
    moved = np.hstack([(walls[:, :2] - mo) @ rotation.T + mt, (walls[:, 2:] - mo) @ rotation.T + mt])
    figure, axes = plt.subplots(figsize=(12, 12))
    for stamp, pose in zip(ref_stamps, ref_poses):
        scan = _nearest(log, stamp)
        ranges = np.where(np.isfinite(scan.ranges) & (scan.ranges < 20.0), scan.ranges, np.nan)
        angles = scan.angles + pose[2]
        axes.plot(pose[0] + ranges * np.cos(angles), pose[1] + ranges * np.sin(angles), ',', color='0.6')
    for x1, y1, x2, y2 in moved:
        axes.plot([x1, x2], [y1, y2], '-', color='tab:red', linewidth=0.6)
    axes.set_aspect('equal')
    axes.set_title('MIT CSAIL: the reference map (grey) and the walls of offline_nav --slam (red)')
    axes.set_xlabel('m')
    figure.savefig(path, dpi=80, bbox_inches='tight')
    print(f'wrote {path}')


def _nearest(log: RobotLog, stamp: float) -> ScanRecord:
    stamps = np.array([s.stamp for s in log.scans])
    return log.scans[int(np.argmin(np.abs(stamps - stamp)))]


if __name__ == '__main__':
    started = time.monotonic()
    status = main()
    print(f'({time.monotonic() - started:.0f} s)')
    sys.exit(status)
