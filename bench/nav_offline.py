"""Benchmark: pluto_nav's localization accuracy in the simulator, offline (no ROS, no DDS).

The simulated robot (``wurde_drivers.sim.SimRobot``, odometry noise trans=0.05 rot=0.05
drift=0.02) drives a route planned through each map; a 361-beam laser (1 cm noise, cm units)
mounted 0.2 m ahead scans every 0.2 s.  ``PoseFilter`` predicts with the odometry increment of
the laser between scans (covariance from ``pluto_nav.odometry_model``) and updates with the
scan's lines.  The table compares the filter's laser pose, and dead reckoning alone, with the
simulator's truth: the shipped maps ``config/maps/*.xml`` and random maps (``random_maps.py`` in
pluto_nav's tests, a stand-in until ``wurde_drivers.sim.generate`` lands).  Nothing is tuned to
any of them.  A second table starts the filter 0.5 m and 10 degrees off (four directions) and
reports how far the robot drove before the error fell below 10 cm for good.

Targets: position RMSE <= 5 cm and heading RMSE <= 1 degree over >= 200 m per map, the error
never above 0.3 m; back under 10 cm within 5 m from the wrong start.  Exit status 1 if missed.

Usage: ``python bench/nav_offline.py [--length 200] [--random 5] [--seed 1]`` inside
``source env.sh`` (it reads the source trees, no build needed).  About a minute.
"""

from __future__ import annotations

import argparse
import math
import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
for _path in ('src/pluto_nav', 'src/pluto_nav/test', 'src/wurde_drivers'):
    sys.path.insert(0, str(ROOT / _path))

import numpy as np  # noqa: E402
from wurde_drivers.sim.mapfile import load_map  # noqa: E402

from nav_sim import run  # noqa: E402
from random_maps import random_map  # noqa: E402

TARGET_XY = 0.05
TARGET_THETA = math.radians(1.0)
DIVERGED = 0.3
RECOVER_M = 5.0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--length', type=float, default=200.0, help='metres per map [200]')
    parser.add_argument('--random', type=int, default=5, help='random maps [5]')
    parser.add_argument('--seed', type=int, default=1, help='first random map seed [1]')
    args = parser.parse_args(argv)
    worlds = [load_map(path) for path in sorted((ROOT / 'config' / 'maps').glob('*.xml'))]
    worlds += [random_map(args.seed + k) for k in range(args.random)]
    ok = True
    print(f'PoseFilter in the simulator: {args.length:.0f} m per map, odometry noise trans=0.05 '
          'rot=0.05 drift=0.02, laser 361 beams 1 cm noise at x=0.2 m')
    print(f'{"map":<15}{"driven m":>9}{"scans":>7}{"rmse cm":>9}{"rmse deg":>9}{"max cm":>8}'
          f'{"max deg":>8}{"odo cm":>9}{"odo deg":>8}{"upd %":>7}{"lines":>6}{"nis":>6}{"s":>6}')
    totals = []
    for index, world in enumerate(worlds):
        started = time.monotonic()
        result = run(world, length_m=args.length, seed=1000 + index)
        xy, theta, odo_xy, odo_theta = result.rmse()
        updated = 100.0 * float(np.mean(result.matches[1:] > 0))
        print(f'{world.name:<15}{result.driven:>9.1f}{len(result.distance) - 1:>7}'
              f'{100 * xy:>9.2f}{math.degrees(theta):>9.3f}{100 * result.error_xy.max():>8.1f}'
              f'{math.degrees(result.error_theta.max()):>8.2f}{100 * odo_xy:>9.0f}'
              f'{math.degrees(odo_theta):>8.1f}{updated:>7.1f}{np.mean(result.matches[1:]):>6.1f}'
              f'{np.nanmean(result.nis):>6.2f}{time.monotonic() - started:>6.1f}', flush=True)
        ok &= (xy <= TARGET_XY and theta <= TARGET_THETA and result.error_xy.max() < DIVERGED
               and result.driven >= args.length - 0.5 and not result.bumped)
        totals.append((result.driven, xy, theta, odo_xy, odo_theta))
    driven = np.array([t[0] for t in totals])
    pooled = [math.sqrt(np.sum(driven * np.array([t[k] for t in totals]) ** 2) / driven.sum())
              for k in (1, 2, 3, 4)]
    print(f'{"all (pooled)":<15}{driven.sum():>9.1f}{"":>7}{100 * pooled[0]:>9.2f}'
          f'{math.degrees(pooled[1]):>9.3f}{"":>16}{100 * pooled[2]:>9.0f}'
          f'{math.degrees(pooled[3]):>8.1f}')
    print()
    print('Wrong start: 0.5 m and 10 deg off (initial sigma 0.5 m, 10 deg); metres driven until '
          'the error stays under 10 cm')
    print(f'{"map":<15}{"0 deg":>8}{"90 deg":>8}{"180 deg":>8}{"270 deg":>8}'
          f'{"rmse after 5 m cm":>19}')
    for index, world in enumerate(worlds):
        recovered, after = [], []
        for k in range(4):
            heading = math.radians(10.0) * (1 if k % 2 else -1)
            offset = (0.5 * math.cos(k * math.pi / 2), 0.5 * math.sin(k * math.pi / 2), heading)
            result = run(world, length_m=12.0, seed=2000 + 4 * index + k, offset=offset,
                         start_sigma=(0.5, math.radians(10.0)))
            recovered.append(result.recovered_after(0.10))
            after.append(result.rmse(start_m=RECOVER_M)[0])
        print(f'{world.name:<15}' + ''.join(f'{m:>8.2f}' for m in recovered)
              + f'{100 * max(after):>19.2f}', flush=True)
        ok &= max(recovered) <= RECOVER_M
    print('targets met' if ok else 'TARGETS MISSED')
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
