"""Wall segments from an occupancy grid: the outlines of its occupied regions.

One home for turning a grid map (a map_server YAML, a CARMEN map, a grid the slamModule built)
into the walls the suite's map format, the poseModule's line matching, the planners and the
simulator use (Programming with CARMEN 5.1: a map is a grid; ours are walls).  Each occupied
region's outline is traced by contourpy's marching squares between the centres of occupied and
free cells at :data:`OUTLINE_LEVEL` (near the occupied centres, where a laser's points are), after
gaps of one cell are closed, and simplified by Ramer-Douglas-Peucker to within ``tolerance`` (one
cell by default).  The accuracy it keeps: every wall lies within one cell of an occupied region's
edge, and a wall one cell thick becomes the two sides of a thin box, as a wall's two faces are.
Unknown cells count as free (a region is outlined where it meets them too).
"""

from __future__ import annotations

import math

import contourpy
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

__all__ = ['OCCUPIED', 'OUTLINE_LEVEL', 'grid_walls', 'simplify']

#: Where between a free cell's centre (0) and an occupied one's (1) the outline runs: near the
#: occupied centre, which is where the scans' points are on average (at 0.5 the outline would
#: be the cells' edge, half a cell in front of the walls).
OUTLINE_LEVEL = 0.95

#: The occupied cells' value (nav_msgs/OccupancyGrid's).
OCCUPIED = 100


def simplify(polyline: NDArray, tolerance: float) -> NDArray:
    """Ramer-Douglas-Peucker: the corners of ``polyline`` that keep every point within
    ``tolerance`` of the simplified line.

    :param polyline: ``(N, 2)`` points, N >= 1; the first and last are always kept.
    :param tolerance: the largest distance allowed, in the points' units.
    """
    keep = np.zeros(len(polyline), dtype=bool)
    keep[0] = keep[-1] = True
    stack = [(0, len(polyline) - 1)]
    while stack:
        first, last = stack.pop()
        if last - first < 2:
            continue
        a, b = polyline[first], polyline[last]
        between = polyline[first + 1:last]
        direction = b - a
        norm = math.hypot(direction[0], direction[1])
        if norm < 1e-12:
            distance = np.hypot(*(between - a).T)
        else:
            distance = np.abs(direction[0] * (between[:, 1] - a[1]) - direction[1] * (between[:, 0] - a[0])) / norm
        worst = int(np.argmax(distance))
        if distance[worst] > tolerance:
            middle = first + 1 + worst
            keep[middle] = True
            stack += [(first, middle), (middle, last)]
    return polyline[keep]


def grid_walls(cells: ArrayLike, origin: tuple[float, float], resolution: float, *,
               tolerance: float | None = None, min_length: float | None = None) -> NDArray:
    """``(N, 4)`` wall segments (m) along the outlines of the occupied regions (see the module's
    description).

    :param cells: ``cells[row, col]``, row 0 at ``origin``'s y, columns along +x; occupied is
        :data:`OCCUPIED`, anything else free.
    :param origin: ``(x, y)`` of cell (0, 0)'s lower-left corner, m.
    :param resolution: m per cell.
    :param tolerance: how far the simplified outline may stray, m; None: one cell.
    :param min_length: an outline whose extent (its bounding box's diagonal) is shorter is
        dropped, m; None: two cells.
    """
    tolerance = resolution if tolerance is None else tolerance
    min_length = 2 * resolution if min_length is None else min_length
    # A wall seen through gaps (glass, a dotted line of hits) is one wall, not many specks too
    # small to keep: gaps of one cell are closed first.
    closed = ndimage.binary_closing(np.pad(np.asarray(cells) == OCCUPIED, 2), structure=np.ones((3, 3)))[1:-1, 1:-1]
    occupied = closed.astype(np.float64)
    lines = contourpy.contour_generator(z=occupied, name='serial').lines(OUTLINE_LEVEL)
    walls = []
    for line in lines:
        xy = np.asarray(line, dtype=np.float64)
        if len(xy) < 2:
            continue
        corners = simplify(xy, tolerance / resolution)
        if len(corners) < 4 and np.array_equal(xy[0], xy[-1]):
            corners = xy          # a loop smaller than the tolerance (a lone cell): kept as traced
        metres = np.column_stack([origin[0] + (corners[:, 0] - 0.5) * resolution,
                                  origin[1] + (corners[:, 1] - 0.5) * resolution])
        pieces = np.hstack([metres[:-1], metres[1:]])
        lengths = np.hypot(pieces[:, 2] - pieces[:, 0], pieces[:, 3] - pieces[:, 1])
        pieces = pieces[lengths > 1e-9]
        if len(pieces) and np.hypot(*(metres.max(axis=0) - metres.min(axis=0))) >= min_length:
            walls.append(pieces)
    return np.vstack(walls) if walls else np.zeros((0, 4))
