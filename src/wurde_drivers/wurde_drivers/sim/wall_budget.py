"""A clearance budget against the walls, so that a robot in open space is not tested against every
wall at every simulation step (issue 39: the dummy base's contact test was the largest part of its
own work).

The distance from a point ``c`` to the nearest wall, once known, is a ball around ``c`` that no wall
enters.  A move whose swept disc stays inside that ball (both ends' discs do: the ball is convex) is
free, and a bumper whose reach stays inside it touches nothing, without looking at a single wall.
Only when a question leaves the ball is the nearest wall looked up again, from the point asked
about.  The answers are exactly those of the full tests; what it saves is measured by
``bench/sim_step.py``.  (:mod:`.clearance` is the batched geometry of the map tools.)
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .raycast import Segments

__all__ = ['WallBudget']


class WallBudget:
    """The last point whose distance to the nearest wall was looked up, and that distance."""

    def __init__(self, segments: Segments) -> None:
        """No clearance known yet.

        :param segments: the world's walls.
        """
        self._segments = segments
        # (x, y, distance to the nearest wall): one tuple, replaced whole, so that two threads
        # sharing a world never see one point's distance with another point's coordinates.
        self._known: tuple[float, float, float] = (math.nan, math.nan, -math.inf)

    def nearest(self, point: ArrayLike) -> tuple[float, NDArray, int]:
        """The wall nearest to ``point`` (:meth:`Segments.nearest`), kept as the new budget."""
        found = self._segments.nearest(point)
        xy = np.asarray(point, dtype=np.float64).reshape(2)
        self._known = (float(xy[0]), float(xy[1]), found[0])
        return found

    def clear(self, points: Sequence[NDArray], margin: float, *, refresh: bool = True) -> bool:
        """Whether every wall is farther than ``margin`` from each of ``points`` and from the
        segments between them (their convex hull).

        :param points: (x, y) each, as arrays.
        :param margin: a disc's radius (plus any tolerance), or a bumper's reach.
        :param refresh: when the known budget cannot tell, look the nearest wall up from
            ``points[0]`` and decide with that; False: answer False then (the caller looks it up).
        :returns: True only if no wall comes within ``margin`` (never a false True).
        """
        x, y, free = self._known
        if all(math.hypot(p[0] - x, p[1] - y) + margin < free for p in points):
            return True
        if not refresh:
            return False
        first = points[0]
        free = self.nearest(first)[0]
        return all(math.hypot(p[0] - first[0], p[1] - first[1]) + margin < free for p in points)
