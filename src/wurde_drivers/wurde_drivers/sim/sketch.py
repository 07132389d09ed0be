"""The drawing board of the map generator: walls, solid shapes, off-limits regions and places,
with the clearance checks that keep a generated map's free space connected.

A layout (:mod:`.layouts`) draws onto a :class:`Sketch`; before it places a piece of furniture, a
building or an off-limits region it asks :meth:`Sketch.fits` whether the shape keeps a gap from
everything drawn so far.  Shapes that keep more than twice the robot's clearance from each other
and from the walls are islands the robot can drive round, so they never cut the free space in two.
:meth:`Sketch.world` turns the sketch, rotated as a whole if asked, into a :class:`~.world.World`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .clearance import legs_clear, point_clearance
from .world import Place, World, points_in_polygon

__all__ = ['Point', 'Polygon', 'Sketch', 'rectangle', 'regular_polygon']

Point = tuple[float, float]
Polygon = list[Point]

#: Generated coordinates are rounded to this many decimals (0.1 mm): readable files, shared
#: corners stay shared.
DECIMALS = 4


def rectangle(cx: float, cy: float, width: float, height: float, angle: float = 0.0) -> Polygon:
    """The corners (counter-clockwise) of a ``width`` x ``height`` rectangle centred on
    ``(cx, cy)`` and turned by ``angle`` radians."""
    half = [(-width / 2, -height / 2), (width / 2, -height / 2), (width / 2, height / 2),
            (-width / 2, height / 2)]
    return _placed(half, cx, cy, angle)


def regular_polygon(cx: float, cy: float, radius: float, corners: int,
                    angle: float = 0.0) -> Polygon:
    """A regular polygon of ``corners`` corners on a circle of ``radius`` around ``(cx, cy)``."""
    local = [(radius * math.cos(2 * math.pi * k / corners),
              radius * math.sin(2 * math.pi * k / corners)) for k in range(corners)]
    return _placed(local, cx, cy, angle)


def _placed(local: Sequence[Point], cx: float, cy: float, angle: float) -> Polygon:
    c, s = math.cos(angle), math.sin(angle)
    return [(cx + x * c - y * s, cy + x * s + y * c) for x, y in local]


def _box(polygon: Sequence[Point]) -> tuple[float, float, float, float]:
    xs, ys = [x for x, _ in polygon], [y for _, y in polygon]
    return (min(xs), min(ys), max(xs), max(ys))


def _edges(polygon: Sequence[Point]) -> np.ndarray:
    corners = np.asarray(polygon, dtype=np.float64)
    return np.hstack([corners, np.roll(corners, -1, axis=0)])


class Sketch:
    """Everything a generated map holds, in a local frame, plus what has to stay clear."""

    def __init__(self) -> None:
        self.walls: list[tuple[float, float, float, float]] = []
        self.solids: list[Polygon] = []        # closed shapes nothing else may sit inside
        self.offlimits: list[Polygon] = []
        self.places: dict[str, Place] = {}
        self.boundary: Polygon = []             # the outer wall: outside it nothing is free
        self._obstacles: np.ndarray | None = None
        self._enclosures: list[tuple[Polygon, tuple[float, float, float, float]]] = []

    # -- drawing ---------------------------------------------------------------------------------

    def wall(self, a: Point, b: Point) -> None:
        """One wall from ``a`` to ``b`` (skipped when it has no length)."""
        if a != b:
            self.walls.append((*a, *b))
            self._obstacles = None

    def chain(self, points: Sequence[Point], *, closed: bool = False) -> None:
        """Walls through ``points``, back to the first one when ``closed``."""
        ring = list(points) + ([points[0]] if closed else [])
        for a, b in zip(ring, ring[1:]):
            self.wall(a, b)

    def outline(self, polygon: Polygon) -> None:
        """The outer wall, a closed chain: shapes and free points must lie inside it."""
        self.chain(polygon, closed=True)
        self.boundary = polygon

    def solid(self, polygon: Polygon) -> None:
        """A closed shape of walls (furniture, a building)."""
        self.chain(polygon, closed=True)
        self.solids.append(polygon)
        self._enclosures.append((polygon, _box(polygon)))

    def off_limits(self, polygon: Polygon) -> None:
        """An off-limits region: no walls, but later shapes keep their gap from it too."""
        self.offlimits.append(polygon)
        self._enclosures.append((polygon, _box(polygon)))
        self._obstacles = None

    # -- checks ----------------------------------------------------------------------------------

    def obstacles(self) -> np.ndarray:
        """``(N, 4)``: the walls and the edges of the off-limits regions."""
        if self._obstacles is None:
            parts = [np.asarray(self.walls, dtype=np.float64).reshape(-1, 4)]
            parts += [_edges(polygon) for polygon in self.offlimits]
            self._obstacles = np.vstack(parts)
        return self._obstacles

    def _enclosed(self, point: Point) -> bool:
        """Inside a solid or an off-limits region, or outside the outline."""
        if self.boundary and not points_in_polygon([point], self.boundary)[0]:
            return True
        x, y = point
        return any(points_in_polygon([point], polygon)[0]
                   for polygon, (x0, y0, x1, y1) in self._enclosures
                   if x0 <= x <= x1 and y0 <= y <= y1)

    def clearance(self, point: Point) -> float:
        """How far ``point`` is from the nearest wall or off-limits edge; 0 inside a solid or an
        off-limits region."""
        if self._enclosed(point):
            return 0.0
        return float(point_clearance([point], self.obstacles())[0])

    def fits(self, polygon: Polygon, gap: float) -> bool:
        """Whether ``polygon`` keeps more than ``gap`` from every wall and region drawn so far,
        without sitting inside another shape or holding one."""
        edges = _edges(polygon)
        obstacles = self.obstacles()
        if len(obstacles):
            if not legs_clear(edges[:, 0:2], edges[:, 2:4], obstacles, gap).all():
                return False
            ends = np.vstack([obstacles[:, 0:2], obstacles[:, 2:4]])
            x0, y0, x1, y1 = _box(polygon)
            ends = ends[(ends[:, 0] >= x0) & (ends[:, 0] <= x1) & (ends[:, 1] >= y0)
                        & (ends[:, 1] <= y1)]
            if len(ends) and points_in_polygon(ends, polygon).any():
                return False
        return not self._enclosed(polygon[0])

    # -- the result ------------------------------------------------------------------------------

    def world(self, name: str, *, angle: float = 0.0) -> World:
        """The sketch turned by ``angle`` about the origin and moved so that its walls' box starts
        at ``(0, 0)``; that box is the world's bounds."""
        c, s = math.cos(angle), math.sin(angle)
        walls = np.asarray(self.walls, dtype=np.float64).reshape(-1, 4)
        xs = np.concatenate([walls[:, 0] * c - walls[:, 1] * s, walls[:, 2] * c - walls[:, 3] * s])
        ys = np.concatenate([walls[:, 0] * s + walls[:, 1] * c, walls[:, 2] * s + walls[:, 3] * c])
        dx, dy = -float(xs.min()), -float(ys.min())

        def move(x: float, y: float) -> Point:
            return (round(x * c - y * s + dx, DECIMALS), round(x * s + y * c + dy, DECIMALS))

        moved = [(*move(x1, y1), *move(x2, y2)) for x1, y1, x2, y2 in self.walls]
        places = {key: Place(*move(p.x, p.y), round(math.remainder(p.theta + angle, math.tau), 6))
                  for key, p in self.places.items()}
        regions = [[move(x, y) for x, y in polygon] for polygon in self.offlimits]
        box = np.asarray(moved).reshape(-1, 4)
        bounds = (min(box[:, 0].min(), box[:, 2].min()), min(box[:, 1].min(), box[:, 3].min()),
                  max(box[:, 0].max(), box[:, 2].max()), max(box[:, 1].max(), box[:, 3].max()))
        return World(moved, places=places, offlimits=regions, bounds=bounds, name=name)
