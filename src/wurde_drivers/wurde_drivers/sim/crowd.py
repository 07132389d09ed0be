"""Putting the config's people in the world: random walks drawn, every walk checked against the map.

What a ``<person>`` (:mod:`.person_config`) needs the map for happens here, once the map is read
(:func:`~.loading.load_sim` calls :func:`place_people`, so every program that reads a sim config
refuses the same people):

- a ``random="N"`` walk gets its waypoints drawn uniformly from its ``area`` (default: the map's
  bounds) with a generator of the config's seed and the person's name
  (:func:`~.clock.make_rng`), each accepted only where the whole walk passes the checks below:
  every process draws the same walk;
- every walk is refused, with the file and the ``<person>``'s line, where the body would touch a
  wall (at a waypoint, turning on the spot: the body's reach; along a leg: its half width, the
  leg stretched by a box's half length), where it would overlap the robot standing at the
  config's start pose (the robot's radius plus the body's reach; people are wherever the clock
  says when the simulation starts, so a walk over the start could begin inside the robot), or
  where a waypoint lies outside the map.

The checks are the walls' clearance functions the route planner uses (:mod:`.clearance`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from wurde_idl.errors import ConfigError

from .clearance import legs_clear, point_clearance, segment_distances
from .clock import make_rng
from .config import SimConfig
from .people import Body, People, Person
from .person_config import PersonConfig
from .walk import LOOP, Walk
from .world import World

__all__ = ['place_people']

#: Makes the error for a reason, naming the file, the ``<person>``'s line and the person.
Refusal = Callable[[str], ConfigError]

#: Shortest leg (m) of a random walk: a waypoint drawn on top of the last is no walk.
MIN_RANDOM_LEG = 0.5
#: Candidate waypoints drawn at a time, and batches tried per waypoint before giving up.
_BATCH = 64
_BATCHES = 100


def place_people(config: SimConfig, world: World, start: tuple[float, float, float]) -> People:
    """The config's people in ``world``, with the robot at ``start`` (the config's start pose).

    :raises ConfigError: a walk the body cannot walk (file and the ``<person>``'s line).
    """
    members = []
    robot = config.robot.bumpers.radius
    for person in config.people:
        def refuse(reason: str, person: PersonConfig = person) -> ConfigError:
            return ConfigError(config.path, person.line, f'person "{person.name}": {reason}')

        points = person.points
        if person.random:
            rng = make_rng(config.seed, f'person:{person.name}')
            points = _draw(person, world, start[:2], robot, rng, refuse)
        try:
            walk = Walk(points, person.speed, person.pause, person.mode)
        except ValueError as error:
            raise refuse(str(error)) from error
        _check(walk, person.body, world, start[:2], robot, refuse)
        members.append(Person(person.name, person.body, walk))
    return People(tuple(members))


def _stretched(p: NDArray, q: NDArray, by: float) -> tuple[NDArray, NDArray]:
    """Legs ``p``-``q`` ``(L, 2)`` made ``by`` longer at each end (a box's half length)."""
    direction = q - p
    length = np.hypot(direction[:, 0], direction[:, 1])[:, None]
    unit = direction / np.where(length > 0.0, length, 1.0)
    return p - by * unit, q + by * unit


def _point_faults(q: NDArray, body: Body, world: World, start: NDArray,
                  robot: float) -> tuple[NDArray, NDArray]:
    """For waypoints ``q`` ``(N, 2)``: whether the body, turning there, touches a wall, and
    whether it overlaps the robot standing at ``start``."""
    return (point_clearance(q, world.walls) <= body.reach,
            np.hypot(*(q - start).T) <= robot + body.reach)


def _leg_faults(p: NDArray, q: NDArray, body: Body, world: World, start: NDArray,
                robot: float) -> tuple[NDArray, NDArray]:
    """For legs ``p[i]``-``q[i]``: whether the body walking it touches a wall, and whether it
    overlaps the robot standing at ``start`` (a box: its sides, its ends stretch the leg)."""
    a, b = _stretched(p, q, body.half_length if body.is_box else 0.0)
    return (~legs_clear(a, b, world.walls, body.half_width),
            segment_distances(a, b, start, start) <= robot + body.half_width)


def _check(walk: Walk, body: Body, world: World, start: tuple[float, float], robot: float,
           refuse: Refusal) -> None:
    """Refuse the first waypoint or leg of ``walk`` that fails (see the module's docstring)."""
    origin = np.asarray(start, dtype=float)
    bounds = world.bounds
    points = np.array(walk.points)
    wall, near = _point_faults(points, body, world, origin, robot)
    size = f'the robot (radius {robot:g} m) and the person ({body.describe()})'
    for number, (x, y) in enumerate(walk.points, 1):
        where = f'point {number} ({x:g}, {y:g})'
        if not bounds.contains(x, y):
            raise refuse(f'{where} is outside the map\'s bounds {tuple(bounds)}')
        if wall[number - 1]:
            gap = float(point_clearance(points[number - 1], world.walls)[0])
            raise refuse(f'{where} is {gap:.2f} m from a wall: the body ({body.describe()}, '
                         f'reaching {body.reach:.2f} m from its centre) would overlap it')
        if near[number - 1]:
            raise refuse(f'{where} is within {robot + body.reach:.2f} m of the robot\'s start '
                         f'({start[0]:g}, {start[1]:g}): {size} would overlap')
    legs = np.array(walk.legs)                                                  # (L, 2, 2)
    wall, near = _leg_faults(legs[:, 0], legs[:, 1], body, world, origin, robot)
    for (a, b), into_wall, into_robot in zip(walk.legs, wall, near):
        where = f'the leg from ({a[0]:g}, {a[1]:g}) to ({b[0]:g}, {b[1]:g})'
        if into_wall:
            raise refuse(f'{where} passes within {body.half_width:.2f} m of a wall: the body '
                         f'({body.describe()}) would cross it')
        if into_robot:
            raise refuse(f'{where} passes the robot\'s start ({start[0]:g}, {start[1]:g}): {size} '
                         'would overlap')


def _draw(person: PersonConfig, world: World, start: tuple[float, float], robot: float,
          rng: np.random.Generator, refuse: Refusal) -> tuple[tuple[float, float], ...]:
    """``person.random`` waypoints whose walk passes :func:`_check`, drawn from its area."""
    b = world.bounds
    x1, y1, x2, y2 = person.area or (b.xmin, b.ymin, b.xmax, b.ymax)
    low = np.array([max(x1, b.xmin), max(y1, b.ymin)])
    high = np.array([min(x2, b.xmax), min(y2, b.ymax)])
    if np.any(low >= high):
        raise refuse(f'area ({x1:g}, {y1:g}) to ({x2:g}, {y2:g}) lies outside the map\'s bounds')
    origin = np.asarray(start, dtype=float)
    body = person.body
    points: list[NDArray] = []
    while len(points) < person.random:
        closing = person.mode == LOOP and len(points) == person.random - 1
        neighbours = ([points[-1]] if points else []) + ([points[0]] if closing else [])
        for _ in range(_BATCHES):
            candidates = rng.uniform(low, high, size=(_BATCH, 2))
            wall, near = _point_faults(candidates, body, world, origin, robot)
            ok = ~wall & ~near
            for neighbour in neighbours:
                wall, near = _leg_faults(np.broadcast_to(neighbour, candidates.shape), candidates,
                                         body, world, origin, robot)
                ok &= ~wall & ~near & (np.hypot(*(candidates - neighbour).T) >= MIN_RANDOM_LEG)
            if ok.any():
                points.append(candidates[int(np.argmax(ok))])
                break
        else:
            raise refuse(f'no free waypoint {len(points) + 1} of {person.random} found in '
                         f'({low[0]:g}, {low[1]:g}) to ({high[0]:g}, {high[1]:g}) after '
                         f'{_BATCH * _BATCHES} tries: give the walk more room (area) or fewer points')
    return tuple((float(x), float(y)) for x, y in points)
