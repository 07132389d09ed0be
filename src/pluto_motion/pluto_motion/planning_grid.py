"""The motionModule's occupancy grid: where the robot's centre may be, and how far from any wall.

Issue 12 ("Beyond Pluto"): when a map is loaded, moveto plans over it.  The grid is built from the
map's walls and off-limits polygons (config/maps/README.md: "the robot must not go there, but
sensors see through it", so they are obstacles here), with

* :attr:`PlanningGrid.clearance`: metres from each cell centre to the nearest wall or off-limits
  region (0 inside one).  A Euclidean distance transform (``scipy.ndimage``) of the rasterised
  obstacles gives it to within half a cell's diagonal; the cells near the inflation threshold are
  then recomputed exactly against the segments, so the threshold is exact at the cell centres.
* :attr:`PlanningGrid.blocked`: clearance below the robot radius plus a margin (the inflation), or
  outside the map's bounds, or outside the motion rectangle when one is set
  (:meth:`PlanningGrid.restricted`).

``data[iy, ix]`` is the cell whose lower-left corner is ``origin + (ix, iy) * resolution`` (row 0
the lowest y, as in ``nav_msgs/OccupancyGrid``).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage
from wurde_idl.maps import load_map
from wurde_idl.segments import point_clearance

__all__ = ['GridSettings', 'PlanningGrid', 'build_grid', 'grid_from_map_file']

#: Cells above which the grid's resolution is coarsened (memory and search time).
MAX_CELLS = 1_000_000


@dataclasses.dataclass(frozen=True)
class GridSettings:
    """How the grid is made.

    :param radius: the robot's radius, m (config/pluto/sim-config.xml: 0.35).
    :param margin: added to the radius for the inflation, m.  A 0.9 m door then leaves a free neck
        of 0.9 - 2 (radius + margin) = 0.12 m for the centre.
    :param resolution: cell size, m (coarsened on big maps so that at most :data:`MAX_CELLS` cells).
    """

    radius: float = 0.35
    margin: float = 0.04
    resolution: float = 0.04

    def __post_init__(self) -> None:
        for name in ('radius', 'resolution'):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ValueError(f'{name} must be a positive number, not {getattr(self, name)}')
        if not (math.isfinite(self.margin) and self.margin >= 0):
            raise ValueError(f'margin must be a number >= 0, not {self.margin}')

    @property
    def inflation(self) -> float:
        """The clearance (m) below which a cell is blocked."""
        return self.radius + self.margin


def _inside(points: NDArray, polygon: NDArray) -> NDArray:
    """Even-odd test: which of ``points`` ``(P, 2)`` lie inside ``polygon`` ``(K, 2)``."""
    inside = np.zeros(len(points), dtype=bool)
    x, y = points[:, 0], points[:, 1]
    for (x1, y1), (x2, y2) in zip(polygon, np.roll(polygon, -1, axis=0)):
        crosses = (y1 > y) != (y2 > y)
        with np.errstate(divide='ignore', invalid='ignore'):
            at = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
        inside ^= crosses & (x < at)
    return inside


@dataclasses.dataclass(eq=False)
class PlanningGrid:
    """Clearance and blocked cells of a map (build it with :func:`build_grid`)."""

    origin: tuple[float, float]
    resolution: float
    clearance: NDArray
    blocked: NDArray
    settings: GridSettings
    #: The obstacles as segments ``(S, 4)`` (walls and off-limits edges), and the off-limits polygons.
    segments: NDArray = dataclasses.field(repr=False, default_factory=lambda: np.zeros((0, 4)))
    polygons: tuple[NDArray, ...] = ()

    @property
    def shape(self) -> tuple[int, int]:
        return self.blocked.shape

    def cell(self, x: float, y: float) -> tuple[int, int] | None:
        """``(iy, ix)`` of the cell holding ``(x, y)``, or None outside the grid."""
        ix = math.floor((x - self.origin[0]) / self.resolution)
        iy = math.floor((y - self.origin[1]) / self.resolution)
        if 0 <= iy < self.shape[0] and 0 <= ix < self.shape[1]:
            return iy, ix
        return None

    def centre(self, iy: int | NDArray, ix: int | NDArray) -> tuple:
        """The ``(x, y)`` of cell centres."""
        return (self.origin[0] + (np.asarray(ix) + 0.5) * self.resolution,
                self.origin[1] + (np.asarray(iy) + 0.5) * self.resolution)

    def free_at(self, x: float, y: float) -> bool:
        """Whether the cell holding ``(x, y)`` is free (False outside the grid)."""
        c = self.cell(x, y)
        return c is not None and not bool(self.blocked[c])

    def clearance_at(self, x: float, y: float) -> float:
        """The clearance (m) of the cell holding ``(x, y)`` (0 outside the grid)."""
        c = self.cell(x, y)
        return 0.0 if c is None else float(self.clearance[c])

    def line_clearance(self, a: Sequence[float], b: Sequence[float]) -> float:
        """The smallest cell clearance along the straight line from ``a`` to ``b`` (sampled at a
        quarter cell)."""
        n = max(2, int(math.ceil(math.dist(a, b) / (self.resolution / 4))) + 1)
        xs, ys = np.linspace(a[0], b[0], n), np.linspace(a[1], b[1], n)
        ix = np.floor((xs - self.origin[0]) / self.resolution).astype(int)
        iy = np.floor((ys - self.origin[1]) / self.resolution).astype(int)
        if (ix < 0).any() or (iy < 0).any() or (ix >= self.shape[1]).any() or (iy >= self.shape[0]).any():
            return 0.0
        if self.blocked[iy, ix].any():
            return 0.0
        return float(self.clearance[iy, ix].min())

    def restricted(self, inside: Callable[[NDArray, NDArray], NDArray] | None) -> PlanningGrid:
        """A copy whose cells with a centre where ``inside(x, y)`` is False are blocked too (the
        motion rectangle, Pluto 6.3); None: this grid."""
        if inside is None:
            return self
        iy, ix = np.indices(self.shape)
        x, y = self.centre(iy, ix)
        blocked = self.blocked | ~np.asarray(inside(x, y), dtype=bool)
        return dataclasses.replace(self, blocked=blocked)


def _resolution(bounds: tuple[float, float, float, float], wanted: float) -> float:
    area = (bounds[2] - bounds[0]) * (bounds[3] - bounds[1])
    if area / wanted ** 2 <= MAX_CELLS:
        return wanted
    return math.ceil(math.sqrt(area / MAX_CELLS) * 1000) / 1000


def build_grid(walls: ArrayLike, offlimits: Sequence[ArrayLike] = (),
               bounds: Sequence[float] | None = None, settings: GridSettings = GridSettings()) -> PlanningGrid:
    """The grid of a map.

    :param walls: ``(N, 4)`` segments x1, y1, x2, y2 (m).
    :param offlimits: polygons ``(K, 2)`` the robot must not enter.
    :param bounds: xmin, ymin, xmax, ymax; outside is blocked.  None: the box around everything.
    :raises ValueError: no walls and no bounds, a non-finite coordinate, an empty bounds box.
    """
    segments = np.asarray(walls, dtype=np.float64).reshape(-1, 4)
    polygons = tuple(np.asarray(p, dtype=np.float64).reshape(-1, 2) for p in offlimits)
    if not np.isfinite(segments).all() or not all(np.isfinite(p).all() for p in polygons):
        raise ValueError('walls and off-limits corners must be finite numbers')
    edges = [np.column_stack([p, np.roll(p, -1, axis=0)]) for p in polygons]
    obstacles = np.vstack([segments, *edges]) if edges else segments
    if bounds is None:
        if len(obstacles) == 0:
            raise ValueError('a map without walls needs bounds')
        xy = obstacles.reshape(-1, 2)
        bounds = (xy[:, 0].min(), xy[:, 1].min(), xy[:, 0].max(), xy[:, 1].max())
    box = tuple(float(v) for v in bounds)
    if not (box[2] > box[0] and box[3] > box[1]):
        raise ValueError(f'bounds {box} enclose no area')
    res = _resolution(box, settings.resolution)      # type: ignore[arg-type]
    width = int(math.ceil((box[2] - box[0]) / res))
    height = int(math.ceil((box[3] - box[1]) / res))
    origin = (box[0], box[1])
    occupied = np.zeros((height, width), dtype=bool)
    for x1, y1, x2, y2 in obstacles:                 # rasterise: samples a quarter cell apart
        n = max(2, int(math.ceil(math.hypot(x2 - x1, y2 - y1) / (res / 4))) + 1)
        ix = np.clip(np.floor((np.linspace(x1, x2, n) - origin[0]) / res).astype(int), 0, width - 1)
        iy = np.clip(np.floor((np.linspace(y1, y2, n) - origin[1]) / res).astype(int), 0, height - 1)
        occupied[iy, ix] = True
    iy, ix = np.indices((height, width))
    cx, cy = origin[0] + (ix + 0.5) * res, origin[1] + (iy + 0.5) * res
    inside_any = np.zeros((height, width), dtype=bool)
    for p in polygons:
        pick = ((cx >= p[:, 0].min()) & (cx <= p[:, 0].max()) & (cy >= p[:, 1].min()) & (cy <= p[:, 1].max()))
        points = np.column_stack([cx[pick], cy[pick]])
        inside_any[pick] = _inside(points, p)
    occupied |= inside_any
    if occupied.any():
        clearance = ndimage.distance_transform_edt(~occupied) * res
    else:
        clearance = np.full((height, width), np.inf)
    # Exact clearance near the threshold: the transform is off by at most half a cell diagonal.
    threshold = settings.inflation
    near = (np.abs(clearance - threshold) <= res) & ~inside_any
    if near.any():
        points = np.column_stack([cx[near], cy[near]])
        clearance[near] = point_clearance(points, obstacles)
    clearance[inside_any] = 0.0
    blocked = clearance < threshold
    return PlanningGrid(origin, res, clearance, blocked, settings, obstacles, polygons)


def grid_from_map_file(path: str | os.PathLike[str], settings: GridSettings = GridSettings()) -> PlanningGrid:
    """The grid of a map file (any format :func:`wurde_idl.maps.load_map` reads).

    :raises wurde_idl.mapfile.MapError: the file's errors, with file, line and reason.
    """
    data = load_map(path)
    return build_grid(data.walls, data.offlimits, data.bounds, settings)
