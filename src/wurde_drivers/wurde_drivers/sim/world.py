"""The simulated robot's world: walls (line segments), named places, off-limits regions, people.

Modelled on CARMEN's maps (programming-with-carmen.txt, section 5): the walls are what the sensors
see and the robot bumps into; a *place list* names poses (``start``, ``kitchen``) that a user or a
program may send the robot to; *off-limits regions* are polygons the robot must not enter although
nothing physical stops it there (the laser sees through them; planners and the simulated base may
refuse them).  Units are metres and radians, angles counter-clockwise from +x (REP-103).

The world's *people* (:mod:`.people`, from the sim config, :meth:`World.with_people`) move: the
sensing and motion methods take ``at``, a stamp, and then meet the people where they are at that
stamp as well as the walls (without ``at``, the walls alone).

A :class:`World` is immutable once built; the sensors of the simulated robot share one.  Map
files hold a :class:`~wurde_idl.mapfile.MapData` (the format is the suite's, in ``wurde_idl``, so
Pluto's modules read it too); :meth:`World.from_map_data` and :meth:`World.to_map_data` convert,
:mod:`.mapfile` reads and writes files, :mod:`.grid` makes occupancy grids.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Iterable, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray
from wurde_idl.mapfile import Bounds, MapData, Place, polygon_area

from .people import People
from .raycast import EPSILON, Segments
from .shapes import Shapes
from .wall_budget import WallBudget

__all__ = ['Bounds', 'Place', 'World', 'points_in_polygon', 'polygon_area']


def points_in_polygon(points: ArrayLike, polygon: ArrayLike) -> NDArray:
    """Which of ``points`` ``(N, 2)`` lie inside ``polygon`` ``(K, 2)`` (even-odd rule).

    Vectorised over points and edges.  Points exactly on an edge may go either way.
    """
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    corners = np.asarray(polygon, dtype=np.float64).reshape(-1, 2)
    ax, ay = corners[:, 0], corners[:, 1]
    bx, by = np.roll(ax, -1), np.roll(ay, -1)
    px, py = points[:, 0:1], points[:, 1:2]
    straddles = (ay > py) != (by > py)                                   # (N, K)
    with np.errstate(divide='ignore', invalid='ignore'):
        crossing_x = ax + (py - ay) * (bx - ax) / (by - ay)
    crossings = straddles & (px < crossing_x)
    return np.count_nonzero(crossings, axis=1) % 2 == 1


class World:
    """Walls, places and off-limits regions of one map.

    :param walls: ``(N, 4)`` segments ``x1, y1, x2, y2`` in metres; none may have zero length.
    :param places: name -> :class:`Place` (or any ``(x, y, theta)`` / ``(x, y)``).
    :param offlimits: polygons, each ``(K, 2)`` with ``K >= 3`` corners and a non-zero area.
    :param bounds: ``(xmin, ymin, xmax, ymax)``; by default the box around walls, places and
        off-limits regions.
    :param name: the map's name.
    :raises ValueError: on malformed or non-finite input (map files are checked with file and
        line by :func:`~.mapfile.load_map` before they get here).
    """

    def __init__(self, walls: ArrayLike = (), *,
                 places: Mapping[str, Iterable[float]] | None = None,
                 offlimits: Iterable[ArrayLike] = (), bounds: Iterable[float] | None = None,
                 name: str = '') -> None:
        segments = np.array(walls, dtype=np.float64).reshape(-1, 4)
        if not np.all(np.isfinite(segments)):
            raise ValueError('wall coordinates must be finite')
        lengths = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
        if np.any(lengths == 0.0):
            raise ValueError(f'wall {int(np.argmin(lengths))} has zero length')
        self._segments = Segments(segments)
        self._walls_budget = WallBudget(self._segments)
        self.walls: NDArray = self._segments.walls
        self.places: dict[str, Place] = {}
        for place_name, pose in (places or {}).items():
            place = Place(*(float(value) for value in pose))
            if not all(math.isfinite(value) for value in place):
                raise ValueError(f'place {place_name!r} is not finite')
            self.places[place_name] = place
        self.offlimits: list[NDArray] = []
        for polygon in offlimits:
            corners = np.array(polygon, dtype=np.float64).reshape(-1, 2)
            if len(corners) < 3 or not np.all(np.isfinite(corners)) or polygon_area(corners) == 0:
                raise ValueError('an off-limits polygon needs 3 or more finite corners and an area')
            corners.flags.writeable = False
            self.offlimits.append(corners)
        self.bounds = Bounds(*(float(v) for v in bounds)) if bounds is not None \
            else self._enclosing_box()
        if not (self.bounds.xmin < self.bounds.xmax and self.bounds.ymin < self.bounds.ymax):
            raise ValueError(f'empty bounds {tuple(self.bounds)}')
        self.name = name
        #: Moving obstacles; none in a world made from a map alone.
        self.people = People()

    def with_people(self, people: People) -> World:
        """This world with ``people`` in it (the walls, places and regions shared)."""
        other = copy.copy(self)
        other.people = people
        return other

    def shapes_at(self, at: float) -> Shapes:
        """The people's bodies at stamp ``at``."""
        return self.people.shapes_at(at)

    @classmethod
    def from_map_data(cls, data: MapData) -> World:
        """The world of a map file's contents (bounds from the file, or the box around it all).

        :raises ValueError: as the constructor (a :func:`~wurde_idl.mapfile.load_map_data`
            result never does).
        """
        return cls(data.walls, places=data.places, offlimits=data.offlimits, bounds=data.bounds,
                   name=data.name)

    def to_map_data(self) -> MapData:
        """This world as a map file's contents: every number exactly, the bounds always."""
        return MapData(self.name, tuple(map(tuple, self.walls.tolist())), dict(self.places),
                       tuple(tuple(map(tuple, polygon.tolist())) for polygon in self.offlimits),
                       self.bounds)

    def _enclosing_box(self) -> Bounds:
        points = [self.walls[:, 0:2], self.walls[:, 2:4], *self.offlimits,
                  np.array([(p.x, p.y) for p in self.places.values()]).reshape(-1, 2)]
        stacked = np.vstack(points)
        if len(stacked) == 0:
            return Bounds(0.0, 0.0, 1.0, 1.0)
        low, high = stacked.min(axis=0), stacked.max(axis=0)
        high = np.where(high > low, high, low + 1.0)  # a world of one straight wall still has area
        return Bounds(float(low[0]), float(low[1]), float(high[0]), float(high[1]))

    def __repr__(self) -> str:
        return (f'World(name={self.name!r}, walls={len(self.walls)}, places={len(self.places)}, '
                f'offlimits={len(self.offlimits)}, bounds={tuple(self.bounds)}, people={len(self.people)})')

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, World):
            return NotImplemented
        return (self.name == other.name and self.bounds == other.bounds and self.people == other.people
                and self.places == other.places and np.array_equal(self.walls, other.walls)
                and len(self.offlimits) == len(other.offlimits)
                and all(np.array_equal(a, b) for a, b in zip(self.offlimits, other.offlimits)))

    __hash__ = None  # type: ignore[assignment]  # mutable-looking arrays: compare, don't hash

    # -- sensing ---------------------------------------------------------------------------------

    def raycast(self, origin_xy: ArrayLike, angles: ArrayLike,
                max_range: float = math.inf, *, at: float | None = None) -> NDArray:
        """Distance from ``origin_xy`` along each of ``angles`` to the first wall (or person).

        :param origin_xy: ``(x, y)`` in metres, or ``(B, 2)``: one origin per beam (a sonar ring).
        :param angles: ``(B,)`` world-frame directions in radians.
        :param max_range: returned for a beam that meets no wall closer than it.
        :param at: a stamp: the people where they are then block the beams too.
        :returns: ``(B,)`` distances in metres; 0 for a beam that starts on a wall or in a person.
        """
        distance = self._segments.cast(origin_xy, angles, max_range)
        if at is not None and len(self.people):
            np.minimum(distance, self.shapes_at(at).cast(origin_xy, angles, max_range), out=distance)
        return distance

    def distance_to_nearest_wall(self, point: ArrayLike) -> float:
        """Smallest distance in metres from ``point`` to any wall (``inf`` with no walls)."""
        return self._segments.nearest(point)[0]

    def nearest_wall(self, point: ArrayLike) -> tuple[float, NDArray, int]:
        """``(distance, closest point on a wall, index into walls)``; ``(inf, point, -1)`` if none.

        The direction from ``point`` to the closest point tells a bumper ring which bumper hit.
        """
        return self._segments.nearest(point)

    def wall_within(self, point: ArrayLike, reach: float) -> NDArray | None:
        """The closest point of the nearest wall if it is within ``reach`` of ``point``, else None
        (a bumper's question, asked at every simulation step: answered from the clearance
        budget, :mod:`.wall_budget`, while the robot is in open space)."""
        xy = np.asarray(point, dtype=np.float64).reshape(2)
        if self._walls_budget.clear([xy], reach, refresh=False):
            return None
        distance, closest, _ = self._walls_budget.nearest(xy)
        return closest if distance <= reach else None

    # -- motion ----------------------------------------------------------------------------------

    def circle_collides(self, center: ArrayLike, radius: float) -> bool:
        """Whether a disc of ``radius`` at ``center`` touches or overlaps a wall."""
        return self.distance_to_nearest_wall(center) <= radius

    def segment_blocked(self, p: ArrayLike, q: ArrayLike) -> bool:
        """Whether the straight line from ``p`` to ``q`` touches or crosses any wall."""
        return self._segments.intersects(p, q)

    def first_contact(self, start: ArrayLike, end: ArrayLike, radius: float, *,
                      at: float | None = None) -> float:
        """How much of the straight move of a disc (the robot) from ``start`` to ``end`` is free.

        :param at: a stamp: the people, where they are then, stop the disc as walls do.
        :returns: the fraction in ``[0, 1]`` of the move before the disc of ``radius`` touches a
            wall: 1.0 for a free move.  A disc already touching a wall can slide along it or back
            away, but gets 0.0 for a move into it.  The simulated base moves the robot by this
            fraction and reports a bump when it is below 1.
        """
        if radius < 0:
            raise ValueError(f'radius must not be negative, got {radius}')
        ends = np.asarray(start, dtype=np.float64).reshape(2), np.asarray(end, dtype=np.float64).reshape(2)
        # A move that stays clear of every wall by more than sweep_circle's touching tolerance is
        # free without sweeping it against each wall (:mod:`.wall_budget`).
        free = 1.0 if self._walls_budget.clear(ends, radius + 4 * EPSILON) \
            else self._segments.sweep_circle(*ends, radius)
        if at is not None and len(self.people) and free > 0.0:
            free = min(free, self.shapes_at(at).sweep_circle(start, end, radius))
        return free

    def people_within(self, point: ArrayLike, distance: float, at: float) -> list[tuple[int, NDArray]]:
        """The people whose bodies come within ``distance`` of ``point`` at stamp ``at``, in index
        order: ``(person index, where they touch)`` each — the body's point nearest to ``point``,
        or its centre when ``point`` lies inside the body (the side a bumper feels it on)."""
        if not len(self.people):
            return []
        shapes = self.shapes_at(at)
        ids, gaps, closest = shapes.nearest(point)
        touch = np.where((gaps > 0.0)[:, None], closest, shapes.centres())
        return sorted(((int(i), t) for i, g, t in zip(ids, gaps, touch) if g <= distance),
                      key=lambda item: item[0])

    # -- places and off-limits -------------------------------------------------------------------

    def is_off_limits(self, point: ArrayLike) -> bool:
        """Whether ``point`` lies inside an off-limits polygon."""
        xy = np.asarray(point, dtype=np.float64).reshape(1, 2)
        return any(bool(points_in_polygon(xy, polygon)[0]) for polygon in self.offlimits)

    def off_limits_mask(self, points: ArrayLike) -> NDArray:
        """Vectorised :meth:`is_off_limits` over ``(N, 2)`` points: ``(N,)`` booleans."""
        xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        inside = np.zeros(len(xy), dtype=bool)
        for polygon in self.offlimits:
            inside |= points_in_polygon(xy, polygon)
        return inside

    def place(self, name: str) -> Place:
        """The place called ``name``; :raises KeyError: naming the known places."""
        try:
            return self.places[name]
        except KeyError:
            known = ', '.join(sorted(self.places)) or 'none'
            raise KeyError(f'no place {name!r} in map {self.name!r}; known: {known}') from None

    def is_free(self, point: ArrayLike, clearance: float = 0.0) -> bool:
        """Whether ``point`` is inside the bounds, outside off-limits, ``clearance`` from walls."""
        x, y = (float(v) for v in np.asarray(point, dtype=np.float64).reshape(2))
        return (self.bounds.contains(x, y) and not self.is_off_limits((x, y))
                and self.distance_to_nearest_wall((x, y)) > clearance)
