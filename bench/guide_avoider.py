"""Benchmark: the guide's LaserAvoider driving chapter 1's VectorMover, in a kinematic simulation.

Two sets of runs, each on worlds this script generates from seeds (none is a shipped map), with
0.01 m laser noise (:mod:`avoider_sim`, no ROS):

* ``clutter``: one to three boxes (0.2-0.8 m by 0.2-1.0 m) between a start and a goal 6 m on, in
  a room; starts and goals at least 0.2 m clear of the robot's edge.
* ``margin``: a box straight between start and goal, the robot started inside the 0.15 m safety
  margin of its face (0.03-0.15 m from it: late scans let a robot come so near).

Each run ends reached or after 90 simulated seconds.  Reported: reached, touched (the robot's
disc came within its 0.35 m radius of a wall) and the least clearance, for the avoider as it is and,
in the same run, without its scan memory (:mod:`pluto_motion.scan_memory`), and as it was before
the kept side, the fan margin and the 0.15 m Navigator step as well (``side_bias`` =
``fan_margin`` = 0, step 0.1 m, no memory).  These three have a fresh scan at every 20 Hz loop;
``late`` has the SICK's at 38400 baud (every 0.2 s, 0.2 s old) and ``slow`` at 9600 baud (every
0.75 s, 0.75 s old), placed at the pose of their stamps as the LaserAvoider does; ``-arr`` the
same scans taken for scans of where the robot is when it looks (the avoider before
:mod:`pluto_nav.pose_history`).

Usage: ``python bench/guide_avoider.py [--seeds N]`` inside ``source env.sh`` (also in
``make bench-avoid``).
"""

from __future__ import annotations

import argparse
import pathlib
import sys
from typing import Any

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / 'src' / 'pluto_motion' / 'test'))      # avoider_sim, goto_sim


def clutter(seed: int) -> list:
    from goto_sim import box, clearance
    rng = np.random.default_rng(seed)
    cases = []
    for _ in range(40):
        walls = []
        for _ in range(int(rng.integers(1, 4))):
            cx, cy = rng.uniform(1.5, 4.5), rng.uniform(-1.0, 1.0)
            w, h = rng.uniform(0.2, 0.8), rng.uniform(0.2, 1.0)
            walls += box(cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2)
        walls += box(-1.0, -3.0, 7.0, 3.0)
        start = (0.0, rng.uniform(-0.3, 0.3), rng.uniform(-0.5, 0.5))
        goal = (6.0, rng.uniform(-1.0, 1.0))
        if clearance(walls, *start[:2]) >= 0.55 and clearance(walls, *goal) >= 0.55:
            cases.append((walls, start, goal))
    return cases


def margin(seed: int) -> list:
    from goto_sim import box
    rng = np.random.default_rng(seed + 100)
    cases = []
    for _ in range(20):
        w, h = rng.uniform(0.3, 1.2), rng.uniform(0.3, 1.5)
        walls = box(2.0, -h / 2, 2.0 + w, h / 2) + box(-1.0, -3.0, 7.0, 3.0)
        start = (2.0 - rng.uniform(0.38, 0.5), rng.uniform(-0.2, 0.2), rng.uniform(-0.3, 0.3))
        cases.append((walls, start, (5.0 + w / 2, rng.uniform(-0.3, 0.3))))
    return cases


#: The SICK at 38400 baud (chapter 1's and config/pluto's laser): a scan every 0.19 s, reaching
#: the avoider 0.2 s after its centre time (wurde_drivers.sick.facts), both rounded to the loop.
LATE = {'scan_period': 0.2, 'latency': 0.2}
#: The SICK at 9600 baud: every 0.76 s, 0.77 s old.
SLOW = {'scan_period': 0.75, 'latency': 0.75}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--seeds', type=int, default=3, help='worlds sets per kind (40 clutter, 20 margin each)')
    args = parser.parse_args()
    sys.path.insert(0, str(ROOT / 'src' / 'pluto_motion'))
    import avoider_sim
    from pluto_motion.corridor_avoid import AvoidSettings

    radius = AvoidSettings().radius
    # name: settings, the Navigator step, run_avoider's keywords
    variants: dict[str, tuple[AvoidSettings, float, dict[str, Any]]] = {
        'now': (AvoidSettings(), avoider_sim.NAV_TURN_STEP, {}),
        'nomemory': (AvoidSettings(), avoider_sim.NAV_TURN_STEP, {'memory': False}),
        'before': (AvoidSettings(side_bias=0.0, fan_margin=0.0), 0.1, {'memory': False}),
        'late': (AvoidSettings(), avoider_sim.NAV_TURN_STEP, LATE),
        'late-arr': (AvoidSettings(), avoider_sim.NAV_TURN_STEP, {**LATE, 'stamped': False}),
        'slow': (AvoidSettings(), avoider_sim.NAV_TURN_STEP, SLOW),
        'slow-arr': (AvoidSettings(), avoider_sim.NAV_TURN_STEP, {**SLOW, 'stamped': False})}
    print(f'{"worlds":8} {"avoider":10} {"reached":>9} {"touched":>8} {"least clearance":>16}')
    for kind, make in (('clutter', clutter), ('margin', margin)):
        for name, (settings, step, options) in variants.items():
            avoider_sim.NAV_TURN_STEP = step
            runs = [avoider_sim.run_avoider(walls, start, goal, noise=0.01, seed=i, settings=settings, **options)
                    for seed in range(1, args.seeds + 1) for i, (walls, start, goal) in enumerate(make(seed))]
            reached = sum(run.result == 'reached' for run in runs)
            touched = sum(run.min_clearance < radius for run in runs)
            least = min(run.min_clearance for run in runs) - radius
            print(f'{kind:8} {name:10} {reached:>4}/{len(runs):<4} {touched:>8} {least:>+13.3f} m', flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
