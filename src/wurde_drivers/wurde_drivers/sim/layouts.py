"""The three kinds of generated map: rooms off corridors, a maze of corridors, an open outdoor area.

Each layout draws on a :class:`~.sketch.Sketch` with a seeded :class:`random.Random` and returns
it with the world's rotation; :func:`~.generate.random_map` builds the world.  What keeps the
free space that matters connected for a robot of radius 0.35 (plus a margin, ``CLEARANCE``):

* doors are at least :data:`DOOR_MIN` wide (0.9 m, as in ``office.xml``); corridors at least
  2.3 m;
* furniture, pillars, buildings and off-limits regions are islands kept :data:`ISLAND_GAP` (more
  than twice the clearance) from everything else, and furniture keeps away from doors;
* ``start`` lies in a corridor or in the open, more than 1 m from every wall.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable
from dataclasses import dataclass

from .sketch import Point, Polygon, Sketch, rectangle, regular_polygon
from .world import Place

__all__ = ['DOOR_MIN', 'ISLAND_GAP', 'LAYOUTS', 'START_CLEARANCE', 'Layout']

DOOR_MIN = 0.9
DOOR_MAX = 1.3
#: Metres between an island (furniture, building, off-limits region) and anything else.
ISLAND_GAP = 0.9
#: ``start`` is more than this far from every wall (the task asks for 1 m).
START_CLEARANCE = 1.1
#: Other places keep this much room around them.
PLACE_CLEARANCE = 0.6
_TRIES = 40


@dataclass
class Layout:
    """A drawn map: the sketch in its own frame and the angle to turn it by."""

    sketch: Sketch
    angle: float = 0.0


def _furniture(rng: random.Random, cx: float, cy: float) -> Polygon:
    """A desk, a table, a cabinet or a round table at ``(cx, cy)``, turned at random."""
    angle = rng.uniform(0.0, math.pi)
    if rng.random() < 0.3:
        return regular_polygon(cx, cy, rng.uniform(0.25, 0.5), 8, angle)
    return rectangle(cx, cy, rng.uniform(0.5, 1.4), rng.uniform(0.4, 0.9), angle)


def _scatter(rng: random.Random, sketch: Sketch, count: int,
             shape: Callable[[float, float], Polygon],
             area: tuple[float, float, float, float], gap: float = ISLAND_GAP,
             keep_off: tuple[Point, float] | None = None,
             draw: Callable[[Polygon], None] | None = None) -> list[Polygon]:
    """Up to ``count`` shapes centred in ``area`` (xmin, ymin, xmax, ymax) that fit with ``gap``,
    none within ``keep_off[1]`` of the point ``keep_off[0]``; each drawn as a solid (or with
    ``draw``)."""
    placed: list[Polygon] = []
    for _ in range(count * _TRIES):
        if len(placed) == count:
            break
        x0, y0, x1, y1 = area
        polygon = shape(rng.uniform(x0, x1), rng.uniform(y0, y1))
        if keep_off is not None:
            (px, py), distance = keep_off
            if min(math.hypot(x - px, y - py) for x, y in polygon) < distance:
                continue
        if sketch.fits(polygon, gap):
            (draw or sketch.solid)(polygon)
            placed.append(polygon)
    return placed


def _free_point(rng: random.Random, sketch: Sketch, area: tuple[float, float, float, float],
                clearance: float) -> Point | None:
    """A random point of ``area`` with more than ``clearance`` around it, if one is found."""
    for _ in range(_TRIES * 5):
        point = (rng.uniform(area[0], area[2]), rng.uniform(area[1], area[3]))
        if sketch.clearance(point) > clearance:
            return point
    return None


# -- rooms off corridors -------------------------------------------------------------------------

def rooms(rng: random.Random, size: float) -> Layout:
    """Rows of rooms off corridors, the corridors joined by a spine along the west wall.

    Each room has one door (0.9 to 1.3 m) onto its corridor, some a cut corner (a wall at an
    angle), some furniture, one perhaps an off-limits work cell; each gets a place ``roomN``.
    Half of the maps are turned by a random angle as a whole.
    """
    sketch = Sketch()
    width = size
    height = max(10.0, min(size, rng.uniform(0.45, 1.0) * size))
    corridor = rng.uniform(2.3, 3.0)
    depth = rng.uniform(3.5, 6.0)
    units = max(1, int(height // (2 * depth + corridor)))
    depth = (height / units - corridor) / 2
    sketch.outline([(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)])
    rooms_drawn: list[tuple[float, float, float, float, Point]] = []
    junctions = []
    for unit in range(units):
        y0 = unit * height / units
        low, high = y0 + depth, y0 + depth + corridor
        junctions.append((corridor / 2, (low + high) / 2))
        if unit > 0:
            sketch.wall((corridor, y0), (width, y0))          # back to back with the unit below
        for band, door_y in (((y0, low), low), ((high, y0 + height / units), high)):
            sketch.wall((corridor, band[0]), (corridor, band[1]))   # the spine's east wall
            rooms_drawn += _room_row(rng, sketch, corridor, width, band, door_y)
    for index, (x0, y0, x1, y1, door) in enumerate(rooms_drawn):
        _chamfer(rng, sketch, (x0, y0, x1, y1), door, always=index == 0)
        _scatter(rng, sketch, rng.randint(1, 3), lambda x, y: _furniture(rng, x, y),
                 (x0, y0, x1, y1), keep_off=(door, 1.2))
    if len(rooms_drawn) >= 3 and rng.random() < 0.7:
        x0, y0, x1, y1, door = rng.choice(rooms_drawn)
        _scatter(rng, sketch, 1, lambda x, y: rectangle(
            x, y, rng.uniform(1.0, 2.0), rng.uniform(1.0, 2.0), rng.uniform(0, math.pi)),
                 (x0, y0, x1, y1), keep_off=(door, 1.5), draw=sketch.off_limits)
    for index, (x0, y0, x1, y1, _door) in enumerate(rooms_drawn, start=1):
        point = _free_point(rng, sketch, (x0, y0, x1, y1), PLACE_CLEARANCE)
        if point is not None:
            sketch.places[f'room{index}'] = Place(*point, rng.uniform(-math.pi, math.pi))
    sketch.places = {'start': Place(*rng.choice(junctions), 0.0), **sketch.places}
    return Layout(sketch, rng.uniform(0.0, math.pi / 2) if rng.random() < 0.5 else 0.0)


def _room_row(rng: random.Random, sketch: Sketch, x_start: float, x_end: float,
              band: tuple[float, float], door_y: float
              ) -> list[tuple[float, float, float, float, Point]]:
    """Rooms 3 to 6 m wide across ``band`` (y0, y1), doors in the wall at ``door_y``."""
    edges = [x_start]
    while x_end - edges[-1] > 6.0:
        edges.append(edges[-1] + rng.uniform(3.0, 6.0))
    if x_end - edges[-1] < 3.0 and len(edges) > 1:
        edges.pop()
    edges.append(x_end)
    wall_from = x_start
    drawn = []
    for x0, x1 in zip(edges, edges[1:]):
        if x0 != x_start:
            sketch.wall((x0, band[0]), (x0, band[1]))
        door = rng.uniform(DOOR_MIN, min(DOOR_MAX, x1 - x0 - 0.8))
        centre = rng.uniform(x0 + 0.4 + door / 2, x1 - 0.4 - door / 2)
        sketch.wall((wall_from, door_y), (centre - door / 2, door_y))
        wall_from = centre + door / 2
        drawn.append((x0, band[0], x1, band[1], (centre, door_y)))
    sketch.wall((wall_from, door_y), (x_end, door_y))
    return drawn


def _chamfer(rng: random.Random, sketch: Sketch, room: tuple[float, float, float, float],
             door: Point, *, always: bool = False) -> None:
    """Cut one of the two corners away from the door with a wall at an angle (a third of the
    rooms, and the first room always)."""
    if rng.random() > 0.35 and not always:
        return
    x0, y0, x1, y1 = room
    far_y = y1 if abs(door[1] - y0) < abs(door[1] - y1) else y0
    corner_x = rng.choice((x0, x1))
    leg_x = rng.uniform(0.5, min(1.5, (x1 - x0) / 3)) * (1 if corner_x == x0 else -1)
    leg_y = rng.uniform(0.5, min(1.5, (y1 - y0) / 3)) * (1 if far_y == y0 else -1)
    sketch.wall((corner_x + leg_x, far_y), (corner_x, far_y + leg_y))


# -- a maze of corridors -------------------------------------------------------------------------

def maze(rng: random.Random, size: float) -> Layout:
    """A maze of corridors with loops: a braided maze on a lattice of cells 3.2 to 4.5 m wide
    whose corners are jittered by an eighth of a cell (so walls meet at varied angles and no
    corridor is narrower than 2.4 m); pillars, a dead end off limits, places ``p1``, ``p2``..."""
    sketch = Sketch()
    cell = rng.uniform(3.2, 4.5)
    nx = max(3, round(size / cell))
    ny = max(3, round(rng.uniform(0.5, 1.0) * size / cell))
    jitter = 0.12 * cell

    def shake(i: int, n: int) -> float:
        return 0.0 if i in (0, n) else rng.uniform(-jitter, jitter)

    corner = {(i, j): (i * cell + shake(i, nx), j * cell + shake(j, ny))
              for i in range(nx + 1) for j in range(ny + 1)}
    open_walls = _braided_maze(rng, nx, ny)
    sketch.outline([corner[i, 0] for i in range(nx)] + [corner[nx, j] for j in range(ny)]
                   + [corner[i, ny] for i in range(nx, 0, -1)]
                   + [corner[0, j] for j in range(ny, 0, -1)])
    for i in range(nx):
        for j in range(ny):
            if i + 1 < nx and (i, j, 'e') not in open_walls:
                sketch.wall(corner[i + 1, j], corner[i + 1, j + 1])
            if j + 1 < ny and (i, j, 'n') not in open_walls:
                sketch.wall(corner[i, j + 1], corner[i + 1, j + 1])

    def centre(i: int, j: int) -> Point:
        quad = [corner[i, j], corner[i + 1, j], corner[i + 1, j + 1], corner[i, j + 1]]
        return (sum(x for x, _ in quad) / 4, sum(y for _, y in quad) / 4)

    cells = [(i, j) for i in range(nx) for j in range(ny)]
    rng.shuffle(cells)
    start = next(c for c in cells if sketch.clearance(centre(*c)) > START_CLEARANCE)
    ends = [c for c in cells if c != start and _openings(c, open_walls, nx, ny) == 1]
    if ends and rng.random() < 0.8:
        i, j = ends[0]
        cx, cy = centre(i, j)
        quad = [corner[i, j], corner[i + 1, j], corner[i + 1, j + 1], corner[i, j + 1]]
        sketch.off_limits([(cx + 0.7 * (x - cx), cy + 0.7 * (y - cy)) for x, y in quad])
    for i, j in cells[: max(1, len(cells) // 6)]:
        if (i, j) == start:
            continue
        x, y = centre(i, j)
        _scatter(rng, sketch, 1, lambda _x, _y: regular_polygon(
            _x, _y, rng.uniform(0.2, 0.4), rng.choice((4, 6, 8)), rng.uniform(0, math.pi)),
                 (x - 0.4, y - 0.4, x + 0.4, y + 0.4))
    sketch.places['start'] = Place(*centre(*start), rng.uniform(-math.pi, math.pi))
    for i, j in cells[-min(6, len(cells) // 3):]:
        point = _free_point(rng, sketch, _shrunk(centre(i, j), cell / 3), PLACE_CLEARANCE)
        if point is not None and (i, j) != start:
            sketch.places[f'p{len(sketch.places)}'] = Place(*point, 0.0)
    return Layout(sketch, rng.uniform(0.0, math.pi) if rng.random() < 0.4 else 0.0)


def _shrunk(point: Point, half: float) -> tuple[float, float, float, float]:
    return (point[0] - half, point[1] - half, point[0] + half, point[1] + half)


def _braided_maze(rng: random.Random, nx: int, ny: int) -> set[tuple[int, int, str]]:
    """The open inner walls of a maze over ``nx`` x ``ny`` cells: a random spanning tree (depth
    first), then some more walls opened so that corridors form loops.  ``(i, j, 'e')`` is the wall
    east of cell ``(i, j)``, ``(i, j, 'n')`` the one north of it."""
    def wall(a: tuple[int, int], b: tuple[int, int]) -> tuple[int, int, str]:
        (i, j), (k, m) = sorted((a, b))
        return (i, j, 'e') if k == i + 1 else (i, j, 'n')

    def neighbours(c: tuple[int, int]) -> list[tuple[int, int]]:
        i, j = c
        return [(i + di, j + dj) for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1))
                if 0 <= i + di < nx and 0 <= j + dj < ny]

    opened: set[tuple[int, int, str]] = set()
    seen = {(0, 0)}
    stack = [(0, 0)]
    while stack:
        fresh = [n for n in neighbours(stack[-1]) if n not in seen]
        if not fresh:
            stack.pop()
            continue
        chosen = rng.choice(fresh)
        opened.add(wall(stack[-1], chosen))
        seen.add(chosen)
        stack.append(chosen)
    for i in range(nx):
        for j in range(ny):
            for other in ((i + 1, j), (i, j + 1)):
                if other[0] < nx and other[1] < ny and rng.random() < 0.12:
                    opened.add(wall((i, j), other))
    return opened


def _openings(c: tuple[int, int], opened: set[tuple[int, int, str]], nx: int, ny: int) -> int:
    i, j = c
    return sum(w in opened for w in ((i, j, 'e'), (i, j, 'n'), (i - 1, j, 'e'), (i, j - 1, 'n')))


# -- an open outdoor area ------------------------------------------------------------------------

def outdoor(rng: random.Random, size: float) -> Layout:
    """A fenced area (corners cut at angles) with scattered buildings, turned at random
    (rectangles, L shapes, hexagons and other polygons), trees and benches, a pond or a
    construction site off limits; places ``bN`` beside the buildings."""
    sketch = Sketch()
    width = size
    height = max(10.0, rng.uniform(0.6, 1.0) * size)
    fence = _cut_corners(rng, [(0.0, 0.0), (width, 0.0), (width, height), (0.0, height)],
                         max(2.5, 0.12 * min(width, height)))
    sketch.outline(fence)
    area = (0.0, 0.0, width, height)
    big = min(14.0, 0.3 * min(width, height))
    count = max(2, min(20, round(width * height / 300)))
    buildings = _scatter(rng, sketch, count, lambda x, y: _building(rng, x, y, big), area,
                         gap=3.0)
    _scatter(rng, sketch, rng.randint(1, 2), lambda x, y: _region(rng, x, y), area, gap=1.5,
             draw=sketch.off_limits)
    _scatter(rng, sketch, max(3, min(60, round(width * height / 80))),
             lambda x, y: _small_thing(rng, x, y), area)
    start = _free_point(rng, sketch, area, 1.5)
    if start is None:  # pragma: no cover - the open area always has room
        raise RuntimeError('no free start found')
    sketch.places['start'] = Place(*start, rng.uniform(-math.pi, math.pi))
    for index, building in enumerate(buildings, start=1):
        k = rng.randrange(len(building))
        (ax, ay), (bx, by) = building[k], building[(k + 1) % len(building)]
        length = math.hypot(bx - ax, by - ay)
        outward = ((by - ay) / length, -(bx - ax) / length)      # corners run counter-clockwise
        point = ((ax + bx) / 2 + 1.5 * outward[0], (ay + by) / 2 + 1.5 * outward[1])
        if sketch.clearance(point) > PLACE_CLEARANCE:
            sketch.places[f'b{index}'] = Place(*point, math.atan2(-outward[1], -outward[0]))
    return Layout(sketch)


def _cut_corners(rng: random.Random, corners: list[Point], most: float) -> list[Point]:
    """The polygon with some corners cut off by a short wall at an angle."""
    result = []
    for k, (x, y) in enumerate(corners):
        if rng.random() < 0.5:
            result.append((x, y))
            continue
        (px, py), (nx, ny) = corners[k - 1], corners[(k + 1) % len(corners)]
        for ox, oy in ((px, py), (nx, ny)):
            d = rng.uniform(2.0, most) / math.hypot(ox - x, oy - y)
            result.append((x + d * (ox - x), y + d * (oy - y)))
    return result


def _building(rng: random.Random, cx: float, cy: float, big: float) -> Polygon:
    """A building: a turned rectangle, an L shape, a regular polygon or a lopsided one."""
    angle = rng.uniform(0.0, math.pi)
    kind = rng.random()
    if kind < 0.35:
        return rectangle(cx, cy, rng.uniform(3.0, big), rng.uniform(3.0, big), angle)
    if kind < 0.6:
        w, h = rng.uniform(5.0, max(5.5, big)), rng.uniform(5.0, max(5.5, big))
        a, b = rng.uniform(0.35, 0.65) * w, rng.uniform(0.35, 0.65) * h
        ell = [(0, 0), (w, 0), (w, b), (a, b), (a, h), (0, h)]
        return [(cx + (x - w / 2) * math.cos(angle) - (y - h / 2) * math.sin(angle),
                 cy + (x - w / 2) * math.sin(angle) + (y - h / 2) * math.cos(angle))
                for x, y in ell]
    radius = rng.uniform(2.0, big / 2)
    if kind < 0.8:
        return regular_polygon(cx, cy, radius, rng.choice((5, 6, 8)), angle)
    corners = rng.randint(4, 7)
    return [(cx + radius * rng.uniform(0.7, 1.3) * math.cos(angle + math.tau * k / corners),
             cy + radius * rng.uniform(0.7, 1.3) * math.sin(angle + math.tau * k / corners))
            for k in range(corners)]


def _region(rng: random.Random, cx: float, cy: float) -> Polygon:
    """A pond (a polygon of 5 to 9 corners) or a construction site (a turned rectangle)."""
    if rng.random() < 0.5:
        return regular_polygon(cx, cy, rng.uniform(2.0, 5.0), rng.randint(5, 9),
                               rng.uniform(0, math.pi))
    return rectangle(cx, cy, rng.uniform(4, 10), rng.uniform(3, 8), rng.uniform(0, math.pi))


def _small_thing(rng: random.Random, cx: float, cy: float) -> Polygon:
    """A tree, a bench or a bollard."""
    angle = rng.uniform(0.0, math.pi)
    kind = rng.random()
    if kind < 0.5:
        return regular_polygon(cx, cy, rng.uniform(0.2, 0.5), 8, angle)
    if kind < 0.8:
        return rectangle(cx, cy, rng.uniform(1.2, 2.0), rng.uniform(0.4, 0.6), angle)
    return rectangle(cx, cy, 0.3, 0.3, angle)


#: Kind name -> layout function ``(rng, size) -> Layout``.
LAYOUTS: dict[str, Callable[[random.Random, float], Layout]] = {
    'rooms': rooms, 'maze': maze, 'outdoor': outdoor}
