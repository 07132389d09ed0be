"""Benchmark: simulated laser scans per second on one core (issue "simulated robot").

A scan is 361 beams over 180 degrees (a SICK LMS at 0.5 degree), cast with
``World.raycast`` against every wall of a map, from a pose that changes every scan.  Maps: exactly
200 random segments in a 20 m x 20 m square (seed 2005, the issue's case) and the shipped maps of
``config/maps``.  Each figure is the median of 5 runs of about half a second; the process is
pinned to one CPU and numpy's thread pools to one thread (set before numpy is imported).
Goal (issue): 500 scans/s or more on the 200-segment map.

Usage: ``make bench`` or ``python bench/raycast.py`` inside ``source env.sh`` (it reads the source
tree of wurde_drivers, so no build is needed).  No ROS, no DDS.
"""

from __future__ import annotations

import os

for _variable in ('OMP_NUM_THREADS', 'OPENBLAS_NUM_THREADS', 'MKL_NUM_THREADS',
                  'NUMEXPR_NUM_THREADS', 'VECLIB_MAXIMUM_THREADS'):
    os.environ[_variable] = '1'

import argparse  # noqa: E402
import math  # noqa: E402
import pathlib  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / 'src' / 'wurde_drivers'))

import numpy as np  # noqa: E402

from wurde_drivers.sim.mapfile import load_map  # noqa: E402
from wurde_drivers.sim.world import World  # noqa: E402

BEAMS = 361
MAX_RANGE = 30.0
GOAL = 500.0
SEGMENTS = 200
SEED = 2005


def random_world(segments: int = SEGMENTS, seed: int = SEED) -> World:
    """Exactly ``segments`` random walls 0.5-3 m long in a 20 m x 20 m square."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.0, 20.0, (segments, 2))
    headings = rng.uniform(0.0, 2 * math.pi, segments)
    half = 0.5 * rng.uniform(0.5, 3.0, segments)[:, None] * np.column_stack(
        [np.cos(headings), np.sin(headings)])
    return World(np.hstack([centres - half, centres + half]), name=f'random-{segments}')


def poses(world: World, count: int = 64, seed: int = 1) -> list[tuple[np.ndarray, float]]:
    """``count`` poses in the world's bounds at least 0.3 m from any wall."""
    rng = np.random.default_rng(seed)
    box = world.bounds
    found: list[tuple[np.ndarray, float]] = []
    while len(found) < count:
        xy = rng.uniform((box.xmin, box.ymin), (box.xmax, box.ymax))
        if world.distance_to_nearest_wall(xy) > 0.3:
            found.append((xy, float(rng.uniform(-math.pi, math.pi))))
    return found


def scans_per_second(world: World, seconds: float) -> float:
    """Scans per second over one run of about ``seconds``."""
    relative = np.linspace(-math.pi / 2, math.pi / 2, BEAMS)
    schedule = poses(world)
    world.raycast(schedule[0][0], relative, MAX_RANGE)  # warm the buffers
    count = 0
    start = time.perf_counter()
    deadline = start + seconds
    while True:
        for xy, theta in schedule:
            world.raycast(xy, relative + theta, MAX_RANGE)
        count += len(schedule)
        now = time.perf_counter()
        if now >= deadline:
            return count / (now - start)


def main() -> int:
    parser = argparse.ArgumentParser(description='simulated laser scans per second, one core')
    parser.add_argument('--runs', type=int, default=5)
    parser.add_argument('--seconds', type=float, default=0.5, help='length of one run')
    args = parser.parse_args()
    if hasattr(os, 'sched_setaffinity'):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    worlds = [random_world()] + [load_map(ROOT / 'config' / 'maps' / f'{name}.xml')
                                 for name in ('office', 'corridor-loop', 'outdoor')]
    print(f'Simulated laser: {BEAMS} beams over 180 deg, max range {MAX_RANGE:g} m, '
          f'numpy {np.__version__}, one core (CPU {sorted(os.sched_getaffinity(0))})')
    print(f'median of {args.runs} runs of {args.seconds:g} s, a new pose every scan; '
          f'goal >= {GOAL:g} scans/s on the {SEGMENTS}-segment map')
    print(f'{"map":<15} {"segments":>8} {"scans/s":>9} {"us/scan":>8} {"min":>7} {"max":>7} '
          f'{"goal":>6} {"met":>4}')
    verdict = True
    for world in worlds:
        rates = [scans_per_second(world, args.seconds) for _ in range(args.runs)]
        median = statistics.median(rates)
        goal = world.name == f'random-{SEGMENTS}'
        met = median >= GOAL
        verdict &= met or not goal
        print(f'{world.name:<15} {len(world.walls):>8} {median:>9.0f} {1e6 / median:>8.0f} '
              f'{min(rates):>7.0f} {max(rates):>7.0f} {(f">={GOAL:g}" if goal else "-"):>6} '
              f'{(("yes" if met else "NO") if goal else "-"):>4}')
    print('goal met' if verdict else 'goal NOT met')
    return 0 if verdict else 1


if __name__ == '__main__':
    sys.exit(main())
