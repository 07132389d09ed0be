"""Benchmark: Pluto's localization (localModule + poseModule) against the simulator's truth.

Issue 11's table: on the three shipped maps and on randomly generated ones (rooms, maze, outdoor;
:mod:`wurde_drivers.sim.generate`), with odometry noise trans 0.05 / rot 0.05 / drift 0.02, laser
noise 0.01 m and DMU rate noise on (config/pluto), the robot drives a generated route of
``--length`` metres steering by Localization/Pose; the Pose's RMSE against the truth is reported
next to dead reckoning (odometry + DMU, stream 0) and odometry alone, in the same run.  One more run
per map kind starts the localModule 0.5 m and 10 degrees off and reports how far the robot drove
before the Pose error stayed under 10 cm.  Targets: Pose RMSE <= 5 cm and <= 1 degree, never
diverging; recovered within 5 m.

Usage: ``make bench-nav`` or ``python bench/nav_accuracy.py [--length 200] [--generated 3]
[--time-scale 2] [--figure docs/localization-office.png]``.
"""

from __future__ import annotations

import argparse
import math
import pathlib
import shutil
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import nav_run  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--length', type=float, default=200.0, help='route length per map (m)')
    parser.add_argument('--generated', type=int, default=3, help='generated maps (one per kind, cycling)')
    parser.add_argument('--seed', type=int, default=11, help='first seed of generated maps and routes')
    parser.add_argument('--time-scale', type=float, default=2.0, help='simulated seconds per wall second')
    parser.add_argument('--shipped', default='office,corridor-loop,outdoor', help='shipped maps to run')
    parser.add_argument('--no-recovery', action='store_true', help='skip the 0.5 m / 10 degree start runs')
    parser.add_argument('--figure', help='copy the first run\'s plot (PNG) here')
    args = parser.parse_args()
    work, maps = nav_run.bench_setup('make bench-nav', args.shipped, args.generated, args.seed)
    from wurde_drivers.sim.mapfile import load_map
    from wurde_drivers.sim.route import random_route
    print(nav_run.HEADER, flush=True)
    results = []
    for i, (name, path) in enumerate(maps):
        route = random_route(load_map(path), args.seed + 100 + i, args.length)
        result = nav_run.run(name, path, route, work / f'run{i}', time_scale=args.time_scale, seed=args.seed + i,
                             limit_s=3 * args.length / 0.3 / args.time_scale + 120)
        results.append(result)
        print(nav_run.row(result), flush=True)
        if i == 0 and args.figure:
            shutil.copyfile(work / f'run{i}' / 'tour.png', args.figure)
    if not args.no_recovery:
        for i, (name, path) in enumerate(maps):
            route = random_route(load_map(path), args.seed + 200 + i, 15.0)
            result = nav_run.run(f'{name}, start 0.5 m / 10 deg off', path, route, work / f'recovery{i}',
                                 time_scale=args.time_scale, seed=args.seed + i,
                                 start_error=(0.5 * math.cos(i), 0.5 * math.sin(i), math.radians(10.0)))
            results.append(result)
            print(nav_run.row(result), flush=True)
    print(f'(runs in {work})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
