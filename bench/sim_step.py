"""Benchmark: what one step of the simulated base costs, with and without the clearance budget
(issue 39: the dummy base's contact test was the largest part of its own work).

A :class:`~wurde_drivers.sim.robot.SimRobot` wanders each shipped map of ``config/maps`` from its
start place at 0.5 m/s: it turns away (1.5 rad/s for a second) whenever the sonar ahead sees a
wall closer than 0.6 m or a bumper trips, so that it drives along walls, into corners and through
open space.  The same walk (the same seed, the same commands) is stepped twice in one process:
through the world as built (:mod:`wurde_drivers.sim.wall_budget`'s budget) and through one whose
contact and bumper tests look at every wall at every step, as before the budget.  Both walks
must end at the same pose, with the same bumps: the budget changes the cost, not the answers.
Each figure is the median of ``--runs`` runs of ``--steps`` steps of 20 ms (the dummy base's
step); one core, numpy single-threaded.

Usage: ``python bench/sim_step.py [--runs 5] [--steps 3000]`` inside ``source env.sh`` (it
reads the source tree of wurde_drivers).  No ROS, no DDS.
"""

from __future__ import annotations

import os

for _variable in ('OMP_NUM_THREADS', 'OPENBLAS_NUM_THREADS', 'MKL_NUM_THREADS',
                  'NUMEXPR_NUM_THREADS', 'VECLIB_MAXIMUM_THREADS'):
    os.environ[_variable] = '1'

import argparse  # noqa: E402
import pathlib  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / 'src' / 'wurde_drivers'))

import numpy as np  # noqa: E402

from wurde_drivers.sim.mapfile import load_map  # noqa: E402
from wurde_drivers.sim.robot import RobotSpec, SimRobot  # noqa: E402
from wurde_drivers.sim.world import World  # noqa: E402

MAPS = ('office', 'corridor-loop', 'outdoor')
STEP_S = 0.02


class FullTests(World):
    """The world with every wall looked at for every move and every bumper question."""

    def first_contact(self, start, end, radius, *, at=None):  # noqa: ANN001, ANN201 - as World's
        return self._segments.sweep_circle(start, end, radius)

    def wall_within(self, point, reach):  # noqa: ANN001, ANN201 - as World's
        distance, closest, _ = self._segments.nearest(point)
        return closest if distance <= reach else None


def walk(world: World, start: tuple[float, float, float], steps: int) -> tuple[float, tuple[float, ...], int]:
    """Step the wandering robot; ``(CPU seconds of the steps, the final pose, bumps)``."""
    robot = SimRobot(world, RobotSpec(), np.random.default_rng(7), start=start)
    turning, bumps = 0, 0
    used = 0.0
    for _ in range(steps):
        ahead = robot.sonar()[0]
        if robot.bumper_stop:
            bumps += 1
        if turning == 0 and (ahead < 0.6 or robot.bumper_stop):
            turning = 50
        robot.command(0.0 if turning else 0.5, 1.5 if turning else 0.0)
        turning = max(0, turning - 1)
        began = time.process_time()
        robot.step(STEP_S)
        used += time.process_time() - began
    t = robot.truth
    return used, (round(t.x, 9), round(t.y, 9), round(t.theta, 9)), bumps


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--runs', type=int, default=5)
    parser.add_argument('--steps', type=int, default=3000, help='20 ms steps a run')
    args = parser.parse_args()
    if hasattr(os, 'sched_setaffinity'):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    print(f'The simulated base: one 20 ms step of a robot wandering at 0.5 m/s, median of {args.runs} '
          f'runs of {args.steps} steps, one core; numpy {np.__version__}')
    print(f'{"map":<15} {"walls":>6} {"budget us/step":>15} {"full tests us/step":>19} {"saved":>7} {"bumps":>6}')
    same = True
    for name in MAPS:
        world = load_map(ROOT / 'config' / 'maps' / f'{name}.xml')
        full = FullTests(world.walls, places={k: tuple(v) for k, v in world.places.items()}, name=world.name)
        place = world.places.get('start') or next(iter(world.places.values()))
        start = (place.x, place.y, place.theta)
        budget_runs, full_runs = [], []
        for _ in range(args.runs):
            used, end, bumps = walk(load_map(ROOT / 'config' / 'maps' / f'{name}.xml'), start, args.steps)
            budget_runs.append(used)
            used_full, end_full, bumps_full = walk(full, start, args.steps)
            full_runs.append(used_full)
            same &= end == end_full and bumps == bumps_full
        budget = 1e6 * statistics.median(budget_runs) / args.steps
        plain = 1e6 * statistics.median(full_runs) / args.steps
        print(f'{name:<15} {len(world.walls):>6} {budget:>15.1f} {plain:>19.1f} '
              f'{100 * (1 - budget / plain):>6.0f}% {bumps:>6}')
    print('the same walk both ways' if same else 'THE WALKS DIFFER: the budget changed an answer')
    return 0 if same else 1


if __name__ == '__main__':
    sys.exit(main())
