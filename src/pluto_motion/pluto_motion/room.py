"""A room's rectangle from the map, by place name: what the mission explores (issue 13).

The room round a place is found on the motion planner's grid (:mod:`.planning_grid`): the cells
farther than :data:`DOOR_HALF` from any wall or off-limits region form connected open areas
(``scipy.ndimage.label``) in which a door, narrower than twice that, is closed; the place's area,
widened again by that distance, bounds the room (each side the median over the area's columns or
rows, so that neither the bulge in front of a door nor a desk in a corner moves it; a bench along
a whole wall is a wall here).  Explore's rectangle is Pluto 6.3's: the home at the middle of one side (the one the
place is nearest to), facing into the room, ``b`` the half-width and ``h`` the depth, each
``margin`` inside the room's bounds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from .planning_grid import PlanningGrid

__all__ = ['DOOR_HALF', 'ExploreArea', 'explore_area', 'room_bounds']

#: Half the widest door gap that must close between two rooms (m); a room must be wider than twice it.
DOOR_HALF = 0.5


@dataclass(frozen=True)
class ExploreArea:
    """Pluto 6.3's rectangle: home ``x``, ``y``, ``theta`` (into the room), ``b``, ``h``."""

    x: float
    y: float
    theta: float
    b: float
    h: float


def room_bounds(grid: PlanningGrid, x: float, y: float,
                door_half: float = DOOR_HALF) -> tuple[float, float, float, float]:
    """(xmin, xmax, ymin, ymax) of the room round (``x``, ``y``), to a cell or so.

    :raises ValueError: for a place off the grid or within ``door_half`` of a wall.
    """
    cell = grid.cell(x, y)
    labels, _count = ndimage.label(grid.clearance > door_half)
    if cell is None or labels[cell] == 0:
        raise ValueError(f'({x:g}, {y:g}) is not {door_half:g} m clear of the walls: no room round it')
    area = labels == labels[cell]
    rows, columns = np.nonzero(area.any(axis=1))[0], np.nonzero(area.any(axis=0))[0]
    # Each side: the median over the area's columns (rows) of their last cell — in front of a door
    # the area reaches a little nearer the wall line, which one extreme cell would take for the side.
    top = np.median([np.nonzero(area[:, c])[0].max() for c in columns])
    bottom = np.median([np.nonzero(area[:, c])[0].min() for c in columns])
    right = np.median([np.nonzero(area[r, :])[0].max() for r in rows])
    left = np.median([np.nonzero(area[r, :])[0].min() for r in rows])
    (xmin, xmax), (ymin, ymax) = grid.centre(np.array([bottom, top]), np.array([left, right]))
    return (float(xmin) - door_half, float(xmax) + door_half, float(ymin) - door_half, float(ymax) + door_half)


def explore_area(grid: PlanningGrid, x: float, y: float, margin: float) -> ExploreArea:
    """Explore's rectangle for the room round (``x``, ``y``), ``margin`` inside its bounds.

    :raises ValueError: for no room there, or one too small for that margin.
    """
    xmin, xmax, ymin, ymax = room_bounds(grid, x, y)
    width, depth = xmax - xmin - 2 * margin, ymax - ymin - 2 * margin
    if width <= 0 or depth <= 0:
        raise ValueError(f'the room round ({x:g}, {y:g}) is {xmax - xmin:.2f} x {ymax - ymin:.2f} m: '
                         f'no room for a {margin:g} m margin')
    cx, cy = (xmin + xmax) / 2, (ymin + ymax) / 2
    sides = {'south': y - ymin, 'north': ymax - y, 'west': x - xmin, 'east': xmax - x}
    side = min(sides, key=sides.__getitem__)
    if side in ('south', 'north'):
        home_y = ymin + margin if side == 'south' else ymax - margin
        return ExploreArea(cx, home_y, math.pi / 2 if side == 'south' else -math.pi / 2, width / 2, depth)
    home_x = xmin + margin if side == 'west' else xmax - margin
    return ExploreArea(home_x, cy, 0.0 if side == 'west' else math.pi, depth / 2, width)
