"""Benchmark: pluto_nav's line extraction (scans/s) and pose filter (updates/s), on one core.

Line extraction: 361-beam scans (0.5 degree, 1 cm noise) of the office map, cast by the simulator
from 64 free poses, extracted in turn; for information also scans of ``bench/raycast.py``'s 200
random segments (clutter: many short pieces).  Pose filter: a recorded drive of
about 40 m through the office map (odometry increments with their covariances, and the lines of
each scan), replayed through ``PoseFilter.predict`` + ``PoseFilter.update`` from the true start;
the line extraction is not part of this figure.  Each figure is the median of 5 runs of about
half a second; the process is pinned to one CPU and numpy's thread pools to one thread (set before
numpy is imported).  Wall-clock and CPU (process) time are both shown: on a loaded machine the
CPU figure is the one that tells the code's cost.  Goals: 1000 scans/s and 1000 updates/s.

Usage: ``python bench/nav_speed.py`` inside ``source env.sh`` (it reads the source trees of
pluto_nav and wurde_drivers, so no build is needed).  No ROS, no DDS.
"""

from __future__ import annotations

import os

for _variable in ('OMP_NUM_THREADS', 'OPENBLAS_NUM_THREADS', 'MKL_NUM_THREADS',
                  'NUMEXPR_NUM_THREADS', 'VECLIB_MAXIMUM_THREADS'):
    os.environ[_variable] = '1'

import math  # noqa: E402
import pathlib  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
for _path in ('src/pluto_nav', 'src/pluto_nav/test', 'src/wurde_drivers'):
    sys.path.insert(0, str(ROOT / _path))

import numpy as np  # noqa: E402
from wurde_drivers.sim.laser import LaserGeometry, LaserModel  # noqa: E402
from wurde_drivers.sim.mapfile import load_map  # noqa: E402
from wurde_drivers.sim.world import World  # noqa: E402

import nav_sim  # noqa: E402
from pluto_nav.geometry import compose  # noqa: E402
from pluto_nav.lines import extract_lines  # noqa: E402
from pluto_nav.pose_filter import PoseFilter  # noqa: E402
from pluto_nav.wall_map import WallMap  # noqa: E402

GOAL = 1000.0
OFFICE = ROOT / 'config' / 'maps' / 'office.xml'
RANGE_SIGMA = math.hypot(0.01, 0.01 / math.sqrt(12.0))


def office_scans(count: int = 64, seed: int = 1, world: World | None = None) -> list[np.ndarray]:
    """``count`` noisy 361-beam scans from free poses of the office map (or ``world``)."""
    world = load_map(OFFICE) if world is None else world
    box = world.bounds
    rng = np.random.default_rng(seed)
    laser = LaserModel(LaserGeometry(noise_sigma=0.01, mount_x=0.2), rng)
    scans: list[np.ndarray] = []
    while len(scans) < count:
        x, y = rng.uniform((box.xmin, box.ymin), (box.xmax, box.ymax))
        if world.is_free((x, y), 0.4):
            scans.append(laser.scan(world, x, y, rng.uniform(-math.pi, math.pi)))
    return scans


def clutter(segments: int = 200, seed: int = 2005) -> World:
    """``segments`` random walls 0.5-3 m long in a 20 m square (``bench/raycast.py``'s case)."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.0, 20.0, (segments, 2))
    headings = rng.uniform(0.0, 2 * math.pi, segments)
    half = 0.5 * rng.uniform(0.5, 3.0, segments)[:, None] * np.column_stack(
        [np.cos(headings), np.sin(headings)])
    return World(np.hstack([centres - half, centres + half]))


def rate(work: Callable[[], int], seconds: float = 0.5, runs: int = 5) -> tuple[float, float]:
    """Median items/s of ``work`` (which returns how many items it did): wall clock, CPU."""
    walls, cpus = [], []
    for _ in range(runs):
        done, wall0, cpu0 = 0, time.perf_counter(), time.process_time()
        while time.perf_counter() - wall0 < seconds:
            done += work()
        walls.append(done / (time.perf_counter() - wall0))
        cpus.append(done / max(time.process_time() - cpu0, 1e-9))
    return statistics.median(walls), statistics.median(cpus)


def recorded_drive(length_m: float = 40.0, seed: int = 7) -> tuple[list, np.ndarray, WallMap]:
    """``[(increment, covariance, lines)]`` of a simulated drive in the office, its start (the
    true laser pose) and the office's walls."""
    world = load_map(OFFICE)
    record: list = []
    nav_sim.run(world, length_m=length_m, seed=seed, record=record)
    return record, compose(tuple(world.place('start')), nav_sim.MOUNT), WallMap(world.walls)


def main() -> int:
    if hasattr(os, 'sched_setaffinity'):
        os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})
    scans = office_scans()
    counts = [len(extract_lines(s, range_sigma=RANGE_SIGMA)) for s in scans]
    state = {'k': 0}

    def extract_one() -> int:
        extract_lines(scans[state['k'] % len(scans)], range_sigma=RANGE_SIGMA)
        state['k'] += 1
        return 1

    extract_wall, extract_cpu = rate(extract_one)
    cluttered = office_scans(world=clutter())
    clutter_counts = [len(extract_lines(s, range_sigma=RANGE_SIGMA)) for s in cluttered]

    def extract_clutter() -> int:
        extract_lines(cluttered[state['k'] % len(cluttered)], range_sigma=RANGE_SIGMA)
        state['k'] += 1
        return 1

    clutter_wall, clutter_cpu = rate(extract_clutter)
    record, start, wall_map = recorded_drive()
    lines_per_scan = statistics.mean(len(step[2]) for step in record)
    cov0 = np.diag([0.02 ** 2, 0.02 ** 2, math.radians(1.0) ** 2])
    filt = PoseFilter()

    def replay() -> int:
        filt.set_pose(start, cov0)
        for increment, covariance, lines in record:
            filt.predict(increment, covariance)
            filt.update(lines, wall_map)
        return len(record)

    matched = []
    filt.set_pose(start, cov0)
    for increment, covariance, lines in record:
        filt.predict(increment, covariance)
        matched.append(filt.update(lines, wall_map).matches)
    update_wall, update_cpu = rate(replay)
    print(f'pluto_nav speed, one core (numpy {np.__version__}, Python {sys.version.split()[0]})')
    print(f'{"what":<44} {"per s (wall)":>13} {"per s (CPU)":>12} {"goal":>6}')
    print(f'{"extract_lines, 361-beam office scan":<44} {extract_wall:>13.0f} {extract_cpu:>12.0f} '
          f'{GOAL:>6.0f}')
    print(f'{"PoseFilter predict + update":<44} {update_wall:>13.0f} {update_cpu:>12.0f} '
          f'{GOAL:>6.0f}')
    print(f'{"extract_lines, 200 random segments (info)":<44} {clutter_wall:>13.0f} '
          f'{clutter_cpu:>12.0f} {"-":>6}')
    print(f'(office scans: {statistics.mean(counts):.1f} lines each on average, random segments: '
          f'{statistics.mean(clutter_counts):.1f}; drive: {len(record)} scans, '
          f'{lines_per_scan:.1f} lines and {statistics.mean(matched):.1f} matches each)')
    return 0 if min(extract_cpu, update_cpu) >= GOAL else 1


if __name__ == '__main__':
    sys.exit(main())
