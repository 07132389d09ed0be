"""Ray following (pluto_motion.ray_follow), pure: scans from the simulator's raycaster (noise-free),
decisions checked one by one and in closed loop with a robot that drives to each target."""

from __future__ import annotations

import math

import numpy as np
import pytest
from wurde_drivers.sim.laser import LaserGeometry, LaserModel
from wurde_drivers.sim.world import World

from pluto_motion.ray_follow import FOLLOWING, SCANNING, Action, RaySettings, ScanGeometry, decide, scan_points

LASER = LaserModel(LaserGeometry(mount_x=0.2), np.random.default_rng(0))
GEOMETRY = ScanGeometry(mount_x=0.2, max_range=LASER.geometry.max_range)
RADIUS = 0.35


def _box(x0: float, y0: float, x1: float, y1: float) -> list[tuple[float, float, float, float]]:
    c = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return [(*a, *b) for a, b in zip(c, c[1:] + c[:1])]


def _points(world: World, pose: tuple[float, float, float]) -> np.ndarray:
    return scan_points(LASER.scan(world, *pose), pose, GEOMETRY)


def test_scan_points_are_where_the_walls_are() -> None:
    world = World(_box(0, 0, 10, 6))
    pose = (3.0, 2.0, 0.7)
    points = _points(world, pose)
    assert len(points) == 361
    assert max(world.distance_to_nearest_wall(p) for p in points) < 0.01


def test_open_field_follows_the_ray_to_the_goal_then_simple_goto() -> None:
    world = World(_box(0, 0, 40, 40))
    pose = (5.0, 5.0, 0.0)
    d = decide(_points(world, pose), pose, (20.0, 12.0))
    assert d.action is Action.GOTO and not d.nearing and d.status == SCANNING     # a first ray chosen
    assert abs(d.ray - math.atan2(7, 15)) <= math.radians(5)
    ahead = (d.target[0] - 5.0) * math.cos(d.ray) + (d.target[1] - 5.0) * math.sin(d.ray)
    assert ahead == pytest.approx(2.0, abs=0.05)                # the lookahead along the ray
    assert math.dist(d.target, pose[:2]) > 2.0                  # and away from the walls near by
    again = decide(_points(world, pose), pose, (20.0, 12.0), current=d.ray)
    assert again.status == FOLLOWING and again.ray == d.ray
    near = (18.5, 11.0, 0.5)
    d = decide(_points(world, near), near, (20.0, 12.0), current=d.ray)
    assert d.nearing and d.target == (20.0, 12.0) and d.status == FOLLOWING


def test_a_goal_behind_turns_in_place() -> None:
    world = World(_box(0, 0, 40, 40))
    pose = (20.0, 20.0, 0.0)
    d = decide(_points(world, pose), pose, (10.0, 19.0))
    assert d.action is Action.TURN and d.status == SCANNING
    assert abs(d.heading - math.atan2(-1, -10)) < 1e-9


def test_a_wall_in_the_way_picks_an_open_ray_not_the_wall() -> None:
    """A wall 3 m ahead, from y = 2 to y = 14; the goal behind it at (16, 9): the ray must pass
    its end (the south end is nearer), not run at the wall."""
    world = World(_box(0, 0, 30, 20) + [(10, 2, 10, 14)])
    pose = (7.0, 9.0, 0.0)
    d = decide(_points(world, pose), pose, (16.0, 9.0))
    assert d.action is Action.GOTO
    assert abs(d.ray) > math.radians(20)                       # not straight at the wall
    assert world.segment_blocked(pose[:2], d.target) is False
    assert world.distance_to_nearest_wall(d.target) > RADIUS


def test_down_the_middle_of_the_street() -> None:
    """A corridor 2.4 m wide (y 0 .. 2.4); the robot 0.5 m from its south wall."""
    world = World([(0, 0, 30, 0), (0, 2.4, 30, 2.4)])
    pose = (2.0, 0.7, 0.0)
    d = decide(_points(world, pose), pose, (25.0, 1.2))
    assert abs(d.target[1] - 1.2) < 0.1


@pytest.mark.parametrize('name, walls, start, goal', [
    ('round a building', _box(0, 0, 40, 30) + _box(12, 8, 20, 22), (5.0, 15.0, 0.0), (30.0, 15.0)),
    ('round a long wall', _box(0, 0, 40, 30) + [(15, 10, 15, 30)], (5.0, 20.0, 0.0), (30.0, 20.0)),
    ('through a corridor door', _box(0, 0, 20, 12) + [(0, 6, 9, 6), (10.5, 6, 20, 6)], (3.0, 3.0, 0.0), (6.0, 9.5)),
])
def test_closed_loop_reaches_the_goal_without_touching(name, walls, start, goal) -> None:
    """A robot that drives (at most 0.25 m and any turn per step) towards each decision's target,
    or turns, deciding on the points of its last 8 scans (as the motionModule does); it must reach
    the goal within 0.3 m and stay clear of every wall."""
    world = World(walls)
    x, y, theta = start
    ray = None
    recent: list[np.ndarray] = []                # the last scans: the laser does not see its flanks
    for _ in range(600):
        pose = (x, y, theta)
        recent = [*recent[-7:], _points(world, pose)]
        d = decide(np.vstack(recent), pose, goal, current=ray)
        ray = d.ray
        if d.action is Action.TURN:
            theta = d.heading
            continue
        tx, ty = d.target
        step = min(0.25, math.hypot(tx - x, ty - y))
        if step < 1e-9:
            break
        theta = math.atan2(ty - y, tx - x)
        x, y = x + step * math.cos(theta), y + step * math.sin(theta)
        assert world.distance_to_nearest_wall((x, y)) > RADIUS, f'{name}: touched at ({x:.2f}, {y:.2f})'
        if math.dist((x, y), goal) < 0.3:
            break
    assert math.dist((x, y), goal) < 0.3, f'{name}: ended at ({x:.2f}, {y:.2f})'


def test_settings_are_plain_values() -> None:
    assert RaySettings().half_width == 1.5                     # Pluto 6.3's outdoor street
