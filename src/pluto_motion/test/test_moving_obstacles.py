"""The avoidModule sees people move: objects followed from scan to scan, walls, pieces of wall and
standing things never taken for walkers, and a robot driving by hand under laser protection that
times its passage past a person crossing its way or walking at its side, wherever the two would
meet (without the walkers, the guard alone meets the same person).  A kinematic run, no ROS:
deterministic."""

from __future__ import annotations

import math
import pathlib

import numpy as np
import pytest
from goto_sim import LASER
from wurde_drivers.sim.laser import LaserModel
from wurde_drivers.sim.loading import load_sim

from pluto_motion.avoid_command import parse_command
from pluto_motion.avoid_control import AvoidController
from pluto_motion.moving_obstacles import MovingObstacles, MovingSettings

RADIUS, PERSON = 0.35, 0.25
ROOT = pathlib.Path(__file__).resolve().parents[3]
PLUTO, MAPS = ROOT / 'config' / 'pluto', ROOT / 'config' / 'maps'
ANGLES = LASER.theta
VIEW = (LASER.x[0], LASER.y[0], LASER.theta[0], LASER.theta[-1])


def disc_scan(pose: tuple[float, float, float], centre: tuple[float, float], radius: float,
              wall_y: float | None = None) -> np.ndarray:
    """The laser's ranges from ``pose`` (its mount ahead of the centre) to a disc and a wall."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    ox, oy = pose[0] + c * LASER.x[0], pose[1] + s * LASER.x[0]
    world = ANGLES + pose[2]
    dx, dy = np.cos(world), np.sin(world)
    fx, fy = ox - centre[0], oy - centre[1]
    b = fx * dx + fy * dy
    disc = b * b - (fx * fx + fy * fy - radius * radius)
    with np.errstate(invalid='ignore'):
        t = -b - np.sqrt(disc)
    ranges = np.where((disc >= 0) & (t > 0), t, np.inf)
    if wall_y is not None:
        with np.errstate(divide='ignore', invalid='ignore'):
            w = (wall_y - oy) / dy
        ranges = np.minimum(ranges, np.where(w > 0, w, np.inf))
    return np.where(ranges <= 8.0, ranges, np.inf)


def test_a_walker_is_followed_and_a_wall_and_a_standing_person_are_not() -> None:
    movers = MovingObstacles()
    pose = (0.0, 0.0, 0.0)
    for k in range(10):
        t = 0.1 * k
        walker = disc_scan(pose, (3.0, -2.0 + 1.0 * t), PERSON)
        movers.scan(LASER.points(walker), pose, t)
    [track] = movers.moving()
    assert track.velocity == pytest.approx([0.0, 1.0], abs=0.1)
    turned = (0.0, 0.0, math.pi / 2)                            # the robot frame turned a quarter
    [walker] = movers.walkers(turned)
    assert walker.velocity == pytest.approx([1.0, 0.0], abs=0.1)
    assert walker.centre == pytest.approx([-1.1, -3.0], abs=0.08)    # the body's, behind its echoes
    still, wall = MovingObstacles(), MovingObstacles()
    for k in range(10):
        still.scan(LASER.points(disc_scan(pose, (3.0, -1.0), PERSON)), pose, 0.1 * k)
        wall.scan(LASER.points(disc_scan(pose, (30.0, 30.0), PERSON, wall_y=1.5)), pose, 0.1 * k)
    assert still.tracks and not still.moving() and not still.walkers(pose)
    assert not wall.tracks                                       # too wide to be anyone


def test_in_the_office_only_the_person_walks(tmp_path: pathlib.Path) -> None:
    """Driving the office corridor with the simulator's laser (noise on) past a person pacing across
    it: the wall breaks into pieces where its echoes thin out at a grazing angle and where the
    person hides it, and the ends of those pieces move with the robot.  None of them is followed
    as walking; the person is, while walking."""
    text = (PLUTO / 'sim-config.xml').read_text().replace('file="map.xml"', f'file="{MAPS / "office.xml"}"')
    pacer = ('<person name="p0" points="14.80,8.32 14.82,6.67" speed="0.53" pause="1.4" '
             'mode="back-and-forth" height="1.7" radius="0.25"/>')
    (tmp_path / 'sim-config.xml').write_text(text.replace('</sim-config>', f'{pacer}</sim-config>'))
    config, world, _ = load_sim(str(tmp_path / 'sim-config.xml'))
    geometry = next(iter(config.lasers.values()))
    laser, angles = LaserModel(geometry, np.random.default_rng(3)), geometry.beam_angles()
    movers, seen = MovingObstacles(), 0
    for k in range(int(14.0 / geometry.scan_period_s)):
        t = k * geometry.scan_period_s
        pose = (10.0 + 0.5 * t, 7.5, 0.0)
        ranges = laser.scan(world, *pose, at=t)
        echo = np.isfinite(ranges)
        points = np.column_stack((geometry.mount_x + ranges[echo] * np.cos(angles[echo]),
                                  geometry.mount_y + ranges[echo] * np.sin(angles[echo])))
        movers.scan(points, pose, t, (geometry.mount_x, geometry.mount_y, angles[0], angles[-1]))
        [(px, py, _)] = world.people.poses_at(t)
        for walker in movers.walkers(pose):
            centre = walker.centre + pose[:2]
            assert math.dist(centre, (px, py)) < 0.4, f'at {t:.1f} s a walker at {centre} is no person'
            seen += 1
    assert seen >= 20, f'the person was seen walking in only {seen} scans'


def crossing(settings: MovingSettings, speed: float, centre_at: float, side: int) -> tuple[float, float]:
    """Drive along x at 0.6 m/s by hand (laser protection on, a scan every 0.1 s, accelerating at
    most 0.5 m/s^2: config/pluto's drive) while a person walks across x = 5 at ``speed`` from the
    robot's right (``side`` 1) or left (-1), crossing the robot's line when the robot's centre,
    unhindered, would be at ``centre_at``: the least gap between the two bodies, and where the robot
    was at the end (it drives on once the person has crossed)."""
    control = AvoidController()
    control.movers = MovingObstacles(settings)
    command = parse_command(20, [0.6, 0.0], [], [])
    x, tv, wanted, dt, least = 0.0, 0.0, 0.0, 0.05, math.inf
    meet = 1.2 + (centre_at - 0.36) / 0.6          # 1.2 s to reach 0.6 m/s, 0.36 m on the way
    for k in range(int(16.0 / dt)):
        t = k * dt
        if k % 20 == 0:
            control.accept(command, t)
        person = (5.0, side * speed * (t - meet))
        pose = (x, 0.0, 0.0)
        if k % 2 == 0:
            ranges = disc_scan(pose, person, PERSON)
            control.set_laser(list(np.where(np.isfinite(ranges), ranges, 8.0)), LASER.points(ranges), t, t, pose, VIEW)
        control.speed = tv
        order = control.step(t, pose, pose)
        wanted = order.velocity[0] if order is not None else wanted
        tv = min(wanted, tv + 0.5 * dt) if wanted >= tv else max(wanted, tv - 0.5 * dt)
        x += tv * dt
        least = min(least, math.dist((x, 0.0), person) - RADIUS - PERSON)
    return least, x


MEETINGS = np.arange(3.6, 6.5, 0.4)      # ahead of the person's line, at it and past it


@pytest.mark.parametrize(('speed', 'side'), [(0.5, 1), (1.0, 1), (1.0, -1), (1.5, -1)],
                         ids=['0.5 m/s from the right', '1 m/s from the right', '1 m/s from the left',
                              '1.5 m/s from the left'])
def test_a_person_crossing_the_way_or_walking_into_the_side_is_not_met(speed: float, side: int) -> None:
    for centre_at in MEETINGS:
        least, x = crossing(MovingSettings(), speed, centre_at, side)
        assert least > 0.1, f'meeting at {centre_at:.1f} m: came within {least:.2f} m of the person'
        assert x > 6.0, f'meeting at {centre_at:.1f} m: did not drive on once the person had crossed (at x {x:.2f})'
    blind = [crossing(MovingSettings(confirm=10 ** 6), speed, c, side)[0] for c in MEETINGS]   # the guard alone
    assert min(blind) <= 0.0, f'the crossings are no test: without the walkers the least gap was {min(blind):.2f} m'
