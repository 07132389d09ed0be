"""Random indoor maps for the localization tests and ``bench/nav_offline.py``.

A stand-in until ``wurde_drivers.sim.generate`` lands: a rectangular floor of random size,
turned by a random angle, cut into rooms by partition walls with door gaps; partitions are thin
(one segment) or thick (two parallel faces 0.1-0.25 m apart with end caps), outer walls are
sometimes drawn in collinear pieces; furniture boxes and pillars at random angles.  The place
``start`` is in the first room, clear of everything.  Seeded: the same seed gives the same map.
"""

from __future__ import annotations

import math

import numpy as np
from wurde_drivers.sim.world import World

__all__ = ['random_map']

DOOR = (1.3, 2.0)          # m, width of a door gap
CLEAR = 1.0                # m, the start is this far from any wall


def random_map(seed: int) -> World:
    """A random office-like world (see the module's description)."""
    rng = np.random.default_rng(seed)
    width, height = rng.uniform(12.0, 26.0), rng.uniform(9.0, 18.0)
    walls: list[tuple[float, float, float, float]] = []
    _outer(rng, width, height, walls)
    columns = np.sort(rng.uniform(0.25, 0.75, rng.integers(1, 4)) * width)
    columns = columns[np.diff(np.concatenate(([0.0], columns))) > 3.0]
    for x in columns:
        _partition(rng, (x, 0.0), (x, height), walls)
    edges = np.concatenate(([0.0], columns, [width]))
    for left, right in zip(edges[:-1], edges[1:]):
        if right - left > 4.0 and rng.random() < 0.6:
            y = rng.uniform(0.35, 0.65) * height
            _partition(rng, (left, y), (right, y), walls)
    for _ in range(rng.integers(3, 9)):
        _box(rng, rng.uniform(0.5, width - 0.5), rng.uniform(0.5, height - 0.5),
             rng.uniform(0.3, 1.6), rng.uniform(0.3, 1.0), rng.uniform(0.0, math.pi), walls)
    segments = np.array(walls)
    start = _start(rng, segments, edges[1] if len(edges) > 2 else width, height)
    angle, shift = rng.uniform(-math.pi, math.pi), rng.uniform(-5.0, 5.0, 2)
    c, s = math.cos(angle), math.sin(angle)
    turn = np.array([[c, -s], [s, c]])
    ends = segments.reshape(-1, 2) @ turn.T + shift
    start_xy = np.asarray(start[:2]) @ turn.T + shift
    return World(ends.reshape(-1, 4), name=f'random-{seed}',
                 places={'start': (*start_xy, float(math.remainder(start[2] + angle,
                                                                    2 * math.pi)))})


def _outer(rng: np.random.Generator, width: float, height: float, walls: list) -> None:
    corners = [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)]
    for a, b in zip(corners, corners[1:] + corners[:1]):
        if rng.random() < 0.5:          # drawn in collinear pieces that touch
            cut = rng.uniform(0.3, 0.7)
            mid = (a[0] + cut * (b[0] - a[0]), a[1] + cut * (b[1] - a[1]))
            walls += [(*a, *mid), (*mid, *b)]
        else:
            walls.append((*a, *b))


def _partition(rng: np.random.Generator, a: tuple, b: tuple, walls: list) -> None:
    """A wall from ``a`` to ``b`` with one or two door gaps; thin or thick."""
    length = math.dist(a, b)
    doors = sorted(rng.uniform(0.8, length - 2.4, rng.integers(1, 3)))
    pieces, at = [], 0.0
    for door in doors:
        if door > at + 0.3:
            pieces.append((at, door))
            at = door + rng.uniform(*DOOR)
    if length - at > 0.3:
        pieces.append((at, length))
    ux, uy = (b[0] - a[0]) / length, (b[1] - a[1]) / length
    thick = rng.uniform(0.1, 0.25) if rng.random() < 0.5 else 0.0
    for start, end in pieces:
        p = (a[0] + start * ux, a[1] + start * uy)
        q = (a[0] + end * ux, a[1] + end * uy)
        if thick == 0.0:
            walls.append((*p, *q))
            continue
        nx, ny = -uy * thick / 2, ux * thick / 2
        face1 = (p[0] + nx, p[1] + ny, q[0] + nx, q[1] + ny)
        face2 = (p[0] - nx, p[1] - ny, q[0] - nx, q[1] - ny)
        walls += [face1, face2, (face1[0], face1[1], face2[0], face2[1]),
                  (face1[2], face1[3], face2[2], face2[3])]


def _box(rng: np.random.Generator, x: float, y: float, length: float, depth: float,
         angle: float, walls: list) -> None:
    c, s = math.cos(angle), math.sin(angle)
    local = [(-length / 2, -depth / 2), (length / 2, -depth / 2), (length / 2, depth / 2),
             (-length / 2, depth / 2)]
    corners = [(x + c * u - s * v, y + s * u + c * v) for u, v in local]
    for p, q in zip(corners, corners[1:] + corners[:1]):
        walls.append((*p, *q))


def _start(rng: np.random.Generator, walls: np.ndarray, right: float,
           height: float) -> tuple[float, float, float]:
    """A point of the first room (left of the first partition) at least CLEAR from every wall."""
    world = World(walls)
    for _ in range(2000):
        x, y = rng.uniform(CLEAR, right - CLEAR), rng.uniform(CLEAR, height - CLEAR)
        if world.distance_to_nearest_wall((x, y)) >= CLEAR:
            return x, y, float(rng.uniform(-math.pi, math.pi))
    raise RuntimeError('no free start point; change the seed')
