"""Reproduction: the avoidModule's control against a person pacing across a corridor, no ROS.

The robot drives along the office corridor (y 7.5, heading east from x 10) under the regulator
with laser protection (cmdFlags 21, 0.6 m/s), as a planned moveto drives it; the simulator's laser
(the sim-config's geometry, the people where they are at each scan's stamp) feeds
:class:`pluto_motion.avoid_control.AvoidController`, whose speed reaches the robot 0.1 s later and at
most 0.5 m/s^2 faster or slower (the driveModule's acceleration).  For each start time (the
person's phase) it prints the least gap between the robot's disc and the person's body, and at
the end how many runs touched: the figure behind docs/movement.md's "Among people".

Usage: ``python bench/people_crossing.py`` (config/pluto's robot and office with one person pacing
across the corridor at x 14.8, 0.53 m/s, 1.4 s pauses by the walls: a person ``bench/nav_people.py``
placed), or ``python bench/people_crossing.py SIM_CONFIG`` with another such sim-config.
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
from wurde_drivers.sim.laser import LaserModel
from wurde_drivers.sim.loading import load_sim

RADIUS = 0.35
ROOT = pathlib.Path(__file__).resolve().parents[1]
#: The person of that figure (bench/nav_people.py's office run with one person).
PACER = ('<person name="p0" points="14.80,8.32 14.82,6.67" speed="0.53" pause="1.4" '
         'mode="back-and-forth" height="1.7" radius="0.25"/>')


def pacing_config(directory: pathlib.Path) -> str:
    """config/pluto's sim-config on the office map with :data:`PACER` in it, written to ``directory``."""
    text = (ROOT / 'config' / 'pluto' / 'sim-config.xml').read_text()
    text = text.replace('file="map.xml"', f'file="{ROOT / "config" / "maps" / "office.xml"}"')
    path = directory / 'sim-config.xml'
    path.write_text(text.replace('</sim-config>', f'  {PACER}\n</sim-config>'))
    return str(path)


def run(sim_config: str, t0: float, *, confirm: int = 3, tv_max: float = 0.6, accel: float = 0.5,
        latency: float = 0.1, seconds: float = 25.0) -> tuple[float, float]:
    """One drive from (10, 7.5) east, the person's clock starting at ``t0``: the least gap (m)
    between the robot and any person, and where the robot ended (x)."""
    config, world, _ = load_sim(sim_config)
    geometry = next(iter(config.lasers.values()))
    laser = LaserModel(geometry, np.random.default_rng(1))
    angles = geometry.beam_angles()
    control = AvoidController()
    control.movers = MovingObstacles(MovingSettings(confirm=confirm))
    command = parse_command(21, [tv_max], [0.0, 0.0], [])
    assert command is not None
    x, y, tv, wanted, dt = 10.0, 7.5, 0.0, 0.0, 0.02
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
            control.set_laser(list(np.where(seen, ranges, 8.0)), points, t, t, pose)
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


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('sim_config', nargs='?', help='default: config/pluto with the pacing person')
    parser.add_argument('--confirm', type=int, default=3, help='scans before a track counts as moving')
    args = parser.parse_args()
    gaps = []
    with tempfile.TemporaryDirectory() as work:
        sim_config = args.sim_config or pacing_config(pathlib.Path(work))
        for t0 in np.arange(0.0, 12.0, 0.5):
            least, x = run(sim_config, float(t0), confirm=args.confirm)
            gaps.append(least)
            print(f'start {t0:4.1f} s: least gap {least:+.2f} m, ended at x {x:.2f}')
    print(f'contacts in {sum(g < 0 for g in gaps)} of {len(gaps)} runs')
    return 0


if __name__ == '__main__':
    sys.exit(main())
