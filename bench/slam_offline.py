"""Benchmark: the slamModule's estimation core (pluto_nav.slam_filter) on long loops, no ROS.

The robot of ``src/pluto_nav/test/slam_sim.py`` (odometry noise trans 0.05, rot 0.05, drift 0.02;
laser noise 0.01 m; a 361-beam scan every 0.2 s) drives a loop of ``--length`` metres or more
that comes back to where it started, on the shipped maps (the corridor loop goes round its
block and on past the start; the office and outdoor maps get random goals then the way back) and
on ``--generated`` generated maps (``wurde_drivers.sim.generate`` when the source tree has it,
else ``random_maps`` of the tests).  Per map: the SLAM laser pose's RMSE and maximum error
against the truth, next to odometry alone in the same run; the walls mapped and how far any
point of them lies from the true walls (and how far their ends lie from one true wall); CPU time
per predict + update; then the map is saved and loaded with ``wurde_idl.mapfile`` and a
PoseFilter localizes against it on a new route (``--relocalize`` metres).

A second table measures the cost per update against the number of landmarks in a hall of
pillars (``--hall`` metres square, a pillar every 4 m: 250 walls or so), with the default 30 m
range (every landmark active: the compressed filter is the plain EKF) and with a 10 m range and a
2 m local area, compressed and not.

Targets: pose RMSE <= 10 cm over a 100 m loop with closure; every mapped wall within 10 cm of the
true one; an update well inside the 200 ms between scans with about 100 landmarks.

Usage (inside ``source env.sh``; wurde_idl with mapfile on PYTHONPATH, e.g. main's source):
``python bench/slam_offline.py [--length 100] [--generated 4] [--seed 21] [--relocalize 30]
[--hall 36] [--hall-length 100]``.
"""

from __future__ import annotations

import os

for _variable in ('OMP_NUM_THREADS', 'OPENBLAS_NUM_THREADS', 'MKL_NUM_THREADS',
                  'NUMEXPR_NUM_THREADS', 'VECLIB_MAXIMUM_THREADS'):
    os.environ[_variable] = '1'

import argparse  # noqa: E402
import math  # noqa: E402
import pathlib  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
for _path in ('src/pluto_nav/test', 'src/pluto_nav', 'src/wurde_drivers', 'src/wurde_core'):
    sys.path.insert(0, str(ROOT / _path))

import numpy as np  # noqa: E402
import slam_sim  # noqa: E402
from nav_sim import MOUNT  # noqa: E402
from wurde_drivers.sim.mapfile import load_map  # noqa: E402
from wurde_drivers.sim.world import World  # noqa: E402
from wurde_idl.mapfile import load_map_data, save_map_data  # noqa: E402

from pluto_nav.slam_filter import SlamSettings  # noqa: E402

#: The corridor loop: round the block and on to the far corner, about 126 m.
CORRIDOR_LOOP = ['start', 'corner_nw', 'corner_ne', 'corner_se', 'corner_sw', 'start', 'corner_nw',
                 'corner_ne']
HEADER = ('| map | driven m | SLAM RMSE cm | SLAM max cm | SLAM RMSE deg | odometry RMSE m | '
          'walls | wall max cm | walls > 10 cm | ends max cm | update ms mean / max | '
          'landmarks | reloaded map: PoseFilter RMSE cm |')


COST_HEADER = ('| world | range m | local area m | driven m | landmarks | active (mean) | '
               'update ms mean / p95 / max | SLAM RMSE cm | wall max cm |')


def pillar_hall(size: float, seed: int, spacing: float = 4.0) -> World:
    """A square hall with a rectangular pillar (0.8-1.4 m by 0.7-1 m, turned at random) every
    ``spacing`` metres, and a clear start in the middle."""
    rng = np.random.default_rng(seed)
    walls = [(0.0, 0.0, size, 0.0), (size, 0.0, size, size), (size, size, 0.0, size),
             (0.0, size, 0.0, 0.0)]
    for cx in np.arange(spacing, size - 1.0, spacing):
        for cy in np.arange(spacing, size - 1.0, spacing):
            if abs(cx - size / 2) < 1.0 and abs(cy - size / 2 - 2.0) < 3.0:
                continue                                  # keep the start clear
            angle = rng.uniform(0.0, math.pi)
            c, s = math.cos(angle), math.sin(angle)
            half_l, half_d = rng.uniform(0.8, 1.4) / 2, rng.uniform(0.7, 1.0) / 2
            x, y = cx + rng.uniform(-0.5, 0.5), cy + rng.uniform(-0.5, 0.5)
            corners = [(x + c * u - s * v, y + s * u + c * v) for u, v in
                       ((-half_l, -half_d), (half_l, -half_d), (half_l, half_d), (-half_l, half_d))]
            walls += [(*p, *q) for p, q in zip(corners, corners[1:] + corners[:1])]
    return World(np.array(walls), name=f'pillar-hall-{size:g}',
                 places={'start': (size / 2, size / 2, 0.0)})


def cost(world: World, length: float, seed: int, max_range: float, zone: float) -> str:
    settings = SlamSettings(max_range=max_range, extent_range=max_range, zone_radius=zone)
    run = slam_sim.run(world, slam_sim.loop_route(world, length, np.random.default_rng(seed)),
                       seed=seed, settings=settings)
    active = np.mean([u.active for u in run.updates])
    spent = 1000 * run.update_s
    errors = slam_sim.wall_errors(run.filter.walls(), world)
    return (f'| {world.name} | {max_range:g} | {"all" if zone > 1e3 else f"{zone:g}"} | '
            f'{run.driven:.0f} | {len(run.filter)} | {active:.0f} | {spent.mean():.1f} / '
            f'{np.percentile(spent, 95):.1f} / {spent.max():.0f} | {100 * run.rmse()[0]:.1f} | '
            f'{100 * errors.max():.1f} |')


def generated_maps(count: int, seed: int) -> tuple[str, list]:
    """``count`` generated worlds: ``wurde_drivers.sim.generate`` if present, else the tests'
    ``random_maps``; and which of the two."""
    try:
        from wurde_drivers.sim.generate import KINDS, random_map
    except ImportError:
        import random_maps
        return 'random_maps (tests)', [random_maps.random_map(seed + i) for i in range(count)]
    return 'wurde_drivers.sim.generate', [random_map(seed + i, KINDS[i % len(KINDS)])
                                          for i in range(count)]


def route_for(world, length: float, seed: int) -> np.ndarray:
    if world.name == 'corridor-loop':
        return slam_sim.place_route(world, CORRIDOR_LOOP)
    return slam_sim.loop_route(world, length, np.random.default_rng(seed))


def bench(world, length: float, seed: int, relocalize: float, work: pathlib.Path) -> str:
    run = slam_sim.run(world, route_for(world, length, seed), seed=seed, check_every=100)
    rmse_xy, rmse_theta, odo_xy, _ = run.rmse()
    walls = run.filter.walls()
    errors = slam_sim.wall_errors(walls, world)
    ends = slam_sim.wall_errors_same_wall(walls, world)
    relocalized = '-'
    if relocalize > 0:
        path = work / f'{world.name}.xml'
        save_map_data(run.filter.to_map_data(world.name, mount=MOUNT), path)
        loaded = load_map_data(path)
        again = slam_sim.localize(world, np.array(loaded.walls), loaded.places['start'],
                                  slam_sim.loop_route(world, relocalize,
                                                      np.random.default_rng(seed + 1000)),
                                  seed=seed + 1000, length_m=relocalize)
        relocalized = f'{100 * math.sqrt(float(np.mean(again ** 2))):.1f}'
    spd = '' if run.spd else ' (covariance not SPD!)'
    return (f'| {world.name}{spd} | {run.driven:.0f} | {100 * rmse_xy:.1f} | '
            f'{100 * run.error_xy.max():.1f} | {math.degrees(rmse_theta):.2f} | {odo_xy:.2f} | '
            f'{len(walls)} | {100 * errors.max():.1f} | {int((errors > 0.1).sum())} | '
            f'{100 * ends.max():.1f} | {1000 * run.update_s.mean():.1f} / '
            f'{1000 * run.update_s.max():.0f} | {len(run.filter)} | {relocalized} |')


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--length', type=float, default=100.0, help='loop length per map (m)')
    parser.add_argument('--generated', type=int, default=4, help='generated maps')
    parser.add_argument('--seed', type=int, default=21, help='first seed of maps and routes')
    parser.add_argument('--shipped', default='office,corridor-loop,outdoor', help='shipped maps')
    parser.add_argument('--relocalize', type=float, default=30.0,
                        help='metres of PoseFilter run on the saved map (0: skip)')
    parser.add_argument('--hall', type=float, default=36.0,
                        help='side of the pillar hall for the cost table (m; 0: skip)')
    parser.add_argument('--hall-length', type=float, help='route in the hall (m; default --length)')
    args = parser.parse_args()
    hall_length = args.length if args.hall_length is None else args.hall_length
    worlds = [load_map(ROOT / 'config' / 'maps' / f'{name}.xml')
              for name in args.shipped.split(',') if name]
    source, generated = generated_maps(args.generated, args.seed)
    print(f'command: python bench/slam_offline.py --length {args.length:g} --generated '
          f'{args.generated} --seed {args.seed} --shipped {args.shipped} --relocalize '
          f'{args.relocalize:g} --hall {args.hall:g} --hall-length {hall_length:g}')
    print(f'generated maps from {source}; CPU time per update on one thread')
    print(HEADER)
    print('|' + '---|' * HEADER.count(' |'))
    began = time.monotonic()
    with tempfile.TemporaryDirectory(prefix='wurde-slam-bench-') as work:
        for i, world in enumerate(worlds + generated):
            print(bench(world, args.length, args.seed + i, args.relocalize, pathlib.Path(work)),
                  flush=True)
    if args.hall > 0:
        hall = pillar_hall(args.hall, args.seed)
        print()
        print(COST_HEADER)
        print('|' + '---|' * COST_HEADER.count(' |'))
        for max_range, zone in ((30.0, 2.0), (10.0, 2.0), (10.0, 1e6)):
            print(cost(hall, hall_length, args.seed, max_range, zone), flush=True)
    print(f'({time.monotonic() - began:.0f} s)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
