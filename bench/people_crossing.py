"""Reproduction: the avoidModule's control against a person crossing the robot's way, no ROS.

The robot drives east under the regulator with laser protection (cmdFlags 21, 0.6 m/s), as a
planned moveto drives it; the simulator's laser (the sim-config's geometry, noise on, the people
where they are at each scan's stamp) feeds :class:`pluto_motion.avoid_control.AvoidController`,
whose speed reaches the robot 0.1 s later and at most 0.5 m/s^2 faster or slower (the
driveModule's acceleration).  Each run prints the least gap between the robot's disc and the
person's body and where the robot ended; the summary counts the runs that touched.  Two scenes:

- ``pacer`` (default): the office corridor (y 7.5, from x 10) with one person pacing across it at
  x 14.8, 0.53 m/s, pausing 1.4 s by each wall (a person ``bench/nav_people.py`` placed); a run per
  start time of the person's walk.  The figure behind docs/movement.md's "Among people".
- ``side``: the open ground of config/maps/outdoor.xml (y 5, from x 5) with one person walking
  across x 12 at ``--speed`` from the robot's right or left; a run per place the two would meet
  (the robot's centre, unhindered, from 1.2 m short of the person's line to 1.2 m past it), with
  the walkers followed and, in the same process, with the laser guard alone.
- ``standing``: the same ground, the robot standing (a regulator command of 0 m/s) and one person
  walking at 45 degrees from ahead on its left or right, across its line from 0.5 m behind its
  centre to 0.5 m ahead: with the walkers followed the robot may step forward out of the way (no
  sonar here, so it never backs off).  A person walking straight at its side is not in the laser's
  view (it looks forward from 0.2 m ahead of the centre) until too late.

Usage: ``python bench/people_crossing.py [pacer|side|standing] [--speed M_S]``.
"""

from __future__ import annotations

import argparse
import math
import pathlib
import sys
import tempfile

import numpy as np
from pluto_motion.avoid_command import parse_command
from pluto_motion.avoid_control import AvoidController
from pluto_motion.moving_obstacles import MovingObstacles, MovingSettings
from pluto_motion.passage import PassageSettings
from wurde_drivers.sim.laser import LaserModel
from wurde_drivers.sim.loading import load_sim

RADIUS = 0.35
ROOT = pathlib.Path(__file__).resolve().parents[1]
#: The person of the pacer figure (bench/nav_people.py's office run with one person).
PACER = ('<person name="p0" points="14.80,8.32 14.82,6.67" speed="0.53" pause="1.4" '
         'mode="back-and-forth" height="1.7" radius="0.25"/>')
#: The side scene: the robot's start and the x where the person crosses its line (y 5).
SIDE_START, SIDE_X, SIDE_FROM = (5.0, 5.0), 12.0, 3.0
#: The standing scene's robot: on the same line, away from the map's start (no walk may cross that).
STANDING_AT = (8.0, 5.0)


def sim_config(directory: pathlib.Path, map_name: str, person: str) -> str:
    """config/pluto's sim-config on ``map_name`` with ``person`` in it, written to ``directory``."""
    text = (ROOT / 'config' / 'pluto' / 'sim-config.xml').read_text()
    text = text.replace('file="map.xml"', f'file="{ROOT / "config" / "maps" / map_name}"')
    path = directory / 'sim-config.xml'
    path.write_text(text.replace('</sim-config>', f'  {person}\n</sim-config>'))
    return str(path)


def side_person(speed: float, side: int, x: float = SIDE_X) -> str:
    """One walk across the robot's line at ``x`` at ``speed`` from its right (``side`` 1) or left (-1)."""
    y0, y1 = SIDE_START[1] - side * SIDE_FROM, SIDE_START[1] + side * SIDE_FROM
    return (f'<person name="p0" points="{x},{y0} {x},{y1}" speed="{speed}" pause="0" '
            'mode="back-and-forth" height="1.7" radius="0.25"/>')


def run(sim_config: str, t0: float, *, confirm: int = 3, tv_max: float = 0.6, accel: float = 0.5,
        latency: float = 0.1, seconds: float = 25.0, start: tuple[float, float] = (10.0, 7.5),
        passage: PassageSettings | None = None, movers: MovingSettings | None = None) -> tuple[float, float]:
    """One drive from ``start`` east, the person's clock starting at ``t0``: the least gap (m)
    between the robot and any person, and where the robot ended (x)."""
    config, world, _ = load_sim(sim_config)
    geometry = next(iter(config.lasers.values()))
    laser = LaserModel(geometry, np.random.default_rng(1))
    angles = geometry.beam_angles()
    view = (geometry.mount_x, geometry.mount_y, float(angles[0]), float(angles[-1]))
    control = AvoidController()
    control.movers = MovingObstacles(movers or MovingSettings(confirm=confirm))
    if passage is not None:
        control.passage = passage
    command = parse_command(21, [tv_max], [0.0, 0.0], [])
    assert command is not None
    (x, y), tv, wanted, dt = start, 0.0, 0.0, 0.02
    least, next_scan = math.inf, 0.0
    pending: list[tuple[float, float]] = []
    for k in range(int(seconds / dt)):
        t = t0 + k * dt
        if k % 25 == 0:
            control.accept(command, t)
        pose = (x, y, 0.0)
        if t - t0 >= next_scan:
            next_scan += geometry.scan_period_s
            ranges = laser.scan(world, x, y, 0.0, at=t)
            seen = np.isfinite(ranges)
            points = np.column_stack((geometry.mount_x + ranges[seen] * np.cos(angles[seen]),
                                      geometry.mount_y + ranges[seen] * np.sin(angles[seen])))
            control.set_laser(list(np.where(seen, ranges, 8.0)), points, t, t, pose, view)
        control.speed = tv
        order = control.step(t, pose, pose)
        if order is not None:
            pending.append((t + latency, order.velocity[0]))
        while pending and pending[0][0] <= t:
            wanted = pending.pop(0)[1]
        tv = min(wanted, tv + accel * dt) if wanted >= tv else max(wanted, tv - accel * dt)
        x += tv * dt
        for px, py, _ in world.people.poses_at(t):
            least = min(least, math.dist((x, y), (px, py)) - RADIUS - 0.25)
    return least, x


def pacer(directory: pathlib.Path) -> list[float]:
    config = sim_config(directory, 'office.xml', PACER)
    gaps = []
    for t0 in np.arange(0.0, 12.0, 0.5):
        least, x = run(config, float(t0))
        gaps.append(least)
        print(f'start {t0:4.1f} s: least gap {least:+.2f} m, ended at x {x:.2f}')
    return gaps


def side(directory: pathlib.Path, speed: float) -> list[float]:
    gaps, alone = [], []
    for sign, name in ((1, 'right'), (-1, 'left')):
        config = sim_config(directory, 'outdoor.xml', side_person(speed, sign))
        for offset in np.arange(-1.2, 1.21, 0.3):
            # The robot unhindered: 0.36 m in the 1.2 s to 0.6 m/s, then 0.6 m/s.
            t0 = SIDE_FROM / speed - 1.2 - (SIDE_X + offset - SIDE_START[0] - 0.36) / 0.6
            least, x = run(config, float(t0), start=SIDE_START, seconds=16.0)
            alone.append(run(config, float(t0), start=SIDE_START, seconds=16.0,
                             movers=MovingSettings(confirm=10 ** 6))[0])
            gaps.append(least)
            print(f'from the {name:5s} meeting {offset:+.1f} m: least gap {least:+.2f} m (guard alone '
                  f'{alone[-1]:+.2f} m), ended at x {x:.2f}')
    print(f'the guard alone: contacts in {sum(g < 0 for g in alone)} of {len(alone)} runs, '
          f'least gap {min(alone):+.2f} m; timing the passage: least gap {min(gaps):+.2f} m')
    return gaps


def standing(directory: pathlib.Path, speed: float) -> list[float]:
    gaps, alone = [], []
    for sign, name in ((1, 'right'), (-1, 'left')):
        for offset in np.arange(-0.5, 0.51, 0.25):
            x, y = STANDING_AT[0] + offset, STANDING_AT[1]
            person = (f'<person name="p0" points="{x + SIDE_FROM},{y + sign * SIDE_FROM} '
                      f'{x - SIDE_FROM},{y - sign * SIDE_FROM}" speed="{speed}" pause="0" '
                      'mode="back-and-forth" height="1.7" radius="0.25"/>')
            config = sim_config(directory, 'outdoor.xml', person)
            t0 = SIDE_FROM * math.sqrt(2.0) / speed - 6.0    # the person crosses the robot's line 6 s in
            least, x = run(config, t0, start=STANDING_AT, seconds=12.0, tv_max=0.0)
            alone.append(run(config, t0, start=STANDING_AT, seconds=12.0, tv_max=0.0,
                             movers=MovingSettings(confirm=10 ** 6))[0])
            gaps.append(least)
            print(f'from ahead {name:5s} {offset:+.2f} m from the robot\'s centre: least gap {least:+.2f} m '
                  f'(guard alone {alone[-1]:+.2f} m), moved to x {x:.2f}')
    print(f'the guard alone: contacts in {sum(g < 0 for g in alone)} of {len(alone)} runs; stepping out of '
          f'the way: least gap {min(gaps):+.2f} m')
    return gaps


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('scene', nargs='?', choices=('pacer', 'side', 'standing'), default='pacer')
    parser.add_argument('--speed', type=float, default=1.0, help='the side walker\'s speed, m/s')
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        scene = {'pacer': lambda: pacer(pathlib.Path(work)), 'side': lambda: side(pathlib.Path(work), args.speed),
                 'standing': lambda: standing(pathlib.Path(work), args.speed)}[args.scene]
        gaps = scene()
    print(f'contacts in {sum(g < 0 for g in gaps)} of {len(gaps)} runs')
    return 0


if __name__ == '__main__':
    sys.exit(main())
