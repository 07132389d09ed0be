"""The avoidModule sees people move: objects followed from scan to scan, walls and standing things
never taken for movers, and a robot driving by hand under laser protection that slows for a person
crossing its way before the person is in it (without the prediction, the same crossing ends on
its bumper).  A kinematic run, no ROS: deterministic."""

from __future__ import annotations

import math

import numpy as np
import pytest
from goto_sim import LASER

from pluto_motion.avoid_command import parse_command
from pluto_motion.avoid_control import AvoidController
from pluto_motion.moving_obstacles import MovingObstacles, MovingSettings

RADIUS, PERSON = 0.35, 0.25
ANGLES = LASER.theta


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
    ahead = movers.predicted(pose)
    assert ahead[:, 1].max() > track.centre[1] + 1.0            # where it will be, not where it is
    still, wall = MovingObstacles(), MovingObstacles()
    for k in range(10):
        still.scan(LASER.points(disc_scan(pose, (3.0, -1.0), PERSON)), pose, 0.1 * k)
        wall.scan(LASER.points(disc_scan(pose, (30.0, 30.0), PERSON, wall_y=1.5)), pose, 0.1 * k)
    assert still.tracks and not still.moving() and len(still.predicted(pose)) == 0
    assert not wall.tracks                                       # too wide to be anyone


def crossing(settings: MovingSettings, speed: float, centre_at: float) -> tuple[float, float]:
    """Drive along x at 0.8 m/s by hand (laser protection on, a scan every 0.1 s, accelerating at
    most 1 m/s^2) while a person walks across x = 5 at ``speed``, crossing the robot's line when
    the robot's centre, unhindered, would be at ``centre_at``: the least gap between the two
    bodies, and where the robot was at the end (it drives on once the person has crossed)."""
    control = AvoidController()
    control.movers = MovingObstacles(settings)
    command = parse_command(20, [0.8, 0.0], [], [])
    x, tv, wanted, dt, least = 0.0, 0.0, 0.0, 0.05, math.inf
    meet = 0.8 + (centre_at - 0.32) / 0.8          # 0.8 s to reach 0.8 m/s, 0.32 m on the way
    for k in range(int(12.0 / dt)):
        t = k * dt
        if k % 20 == 0:
            control.accept(command, t)
        person = (5.0, speed * (t - meet))
        pose = (x, 0.0, 0.0)
        if k % 2 == 0:
            ranges = disc_scan(pose, person, PERSON)
            control.set_laser(list(np.where(np.isfinite(ranges), ranges, 8.0)), LASER.points(ranges), t, t, pose)
        order = control.step(t, pose, pose)
        wanted = order.velocity[0] if order is not None else wanted
        tv = min(wanted, tv + 1.0 * dt) if wanted >= tv else max(wanted, tv - 1.0 * dt)
        x += tv * dt
        least = min(least, math.dist((x, 0.0), person) - RADIUS - PERSON)
    return least, x


@pytest.mark.parametrize(('speed', 'centre_at'), [(1.0, 4.8), (1.0, 5.2), (0.5, 5.6)],
                         ids=['1 m/s ahead', '1 m/s into the side', '0.5 m/s into the side'])
def test_a_person_crossing_the_way_is_not_met(speed: float, centre_at: float) -> None:
    least, x = crossing(MovingSettings(), speed, centre_at)
    assert least > 0.05, f'came within {least:.2f} m of the person'
    assert x > 6.0, f'did not drive on once the person had crossed (at x {x:.2f})'
    blind, _ = crossing(MovingSettings(confirm=10 ** 6), speed, centre_at)    # the guard alone
    assert blind <= 0.0, f'the crossing is no test: without prediction the gap was {blind:.2f} m'
