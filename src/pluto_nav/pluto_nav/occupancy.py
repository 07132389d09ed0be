"""An occupancy grid from scans at known poses, and the walls it shows.

:func:`build_grid` counts, per cell, the beams that ended in it (hits) and the beams that passed
through it (misses): the "counting" or reflection model of CARMEN's and GMapping's maps.  A beam
that saw nothing within range clears the cells along it up to ``free_range``.  A cell is occupied
when at least ``min_hits`` beams ended in it and they are at least ``occupied_ratio`` of the beams
that reached it; free when beams passed and it is not occupied; unknown when no beam reached it.

:func:`grid_walls` turns the occupied cells into wall segments for the suite's map format
(:mod:`wurde_idl.gridwalls`, where every grid map becomes walls: each wall within one cell of
an occupied region's edge).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from wurde_idl import gridwalls

from .geometry import transform_points

__all__ = ['FREE', 'OCCUPIED', 'UNKNOWN', 'Grid', 'build_grid', 'grid_walls']

#: Cell values of :attr:`Grid.cells` (those of nav_msgs/OccupancyGrid).
FREE, OCCUPIED, UNKNOWN = 0, 100, -1


@dataclasses.dataclass(frozen=True)
class Grid:
    """A trinary occupancy grid: ``cells[row, col]`` with row 0 at ``origin``'s y and columns
    along +x (nav_msgs/OccupancyGrid's order); ``origin`` is the lower-left corner of cell (0, 0)."""

    cells: NDArray              # int8: FREE, OCCUPIED or UNKNOWN
    origin: tuple[float, float]
    resolution: float

    @property
    def occupied_points(self) -> NDArray:
        """The centres of the occupied cells, ``(N, 2)`` metres."""
        rows, cols = np.nonzero(self.cells == OCCUPIED)
        return np.column_stack([self.origin[0] + (cols + 0.5) * self.resolution,
                                self.origin[1] + (rows + 0.5) * self.resolution])


def build_grid(poses: ArrayLike, rays: Sequence[tuple[NDArray, NDArray]], *, resolution: float = 0.05,
               max_range: float = 30.0, free_range: float = 10.0, min_hits: int = 2,
               occupied_ratio: float = 0.25) -> Grid:
    """The occupancy grid of scans taken at known laser poses (see the module's description).

    :param poses: ``(N, 3)`` the laser poses ``(x, y, theta)``, one per scan, in the map frame.
    :param rays: per scan ``(angles, ranges)`` in the laser's frame, radians and metres; ``inf``:
        nothing within range, NaN or 0 or less: no reading.
    :param resolution: m per cell.
    :param max_range: m; a range beyond it is taken as nothing within range.
    :param free_range: m a beam that saw nothing clears along its direction.
    :param min_hits: beams that must end in a cell for it to be occupied.
    :param occupied_ratio: the share of the beams reaching a cell that must end in it for it to be
        occupied.
    :returns: the grid, covering every beam's cells with a cell of border.
    """
    poses = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    ends, starts, free_ends = [], [], []
    for pose, (angles, ranges) in zip(poses, rays):
        r = np.asarray(ranges, dtype=np.float64)
        a = np.asarray(angles, dtype=np.float64)
        hit = np.isfinite(r) & (r > 0.0) & (r <= max_range)
        clear = np.isposinf(r) | (np.isfinite(r) & (r > max_range))
        length = np.where(hit, r, np.where(clear, free_range, 0.0))
        keep = length > 0.0
        direction = np.column_stack([np.cos(a[keep]), np.sin(a[keep])])
        ends.append(transform_points(pose, direction[hit[keep]] * r[keep][hit[keep]][:, None]))
        free_ends.append(transform_points(pose, direction * length[keep][:, None]))
        starts.append(np.repeat(pose[None, :2], int(keep.sum()), axis=0))
    hits = np.vstack(ends) if ends else np.zeros((0, 2))
    tips = np.vstack(free_ends) if free_ends else np.zeros((0, 2))
    bases = np.vstack(starts) if starts else np.zeros((0, 2))
    everything = np.vstack([hits, tips, bases]) if len(tips) else np.zeros((1, 2))
    low = np.floor(everything.min(axis=0) / resolution) * resolution - resolution
    high = everything.max(axis=0) + 2 * resolution
    cols, rows = (np.ceil((high - low) / resolution).astype(int) + 1).tolist()
    hit_count = _count(hits, low, resolution, rows, cols)
    miss_count = _ray_misses(bases, tips, low, resolution, rows, cols)
    reached = hit_count + miss_count
    cells = np.full((rows, cols), UNKNOWN, dtype=np.int8)
    cells[reached > 0] = FREE
    occupied = (hit_count >= min_hits) & (hit_count >= occupied_ratio * np.maximum(reached, 1))
    cells[occupied] = OCCUPIED
    return Grid(cells, (float(low[0]), float(low[1])), float(resolution))


def _index(points: NDArray, low: NDArray, resolution: float, rows: int, cols: int) -> NDArray:
    cell = np.floor((points - low) / resolution).astype(np.int64)
    inside = (cell[:, 0] >= 0) & (cell[:, 0] < cols) & (cell[:, 1] >= 0) & (cell[:, 1] < rows)
    return cell[inside, 1] * cols + cell[inside, 0]


def _count(points: NDArray, low: NDArray, resolution: float, rows: int, cols: int) -> NDArray:
    flat = _index(points, low, resolution, rows, cols)
    return np.bincount(flat, minlength=rows * cols).reshape(rows, cols)


def _ray_misses(bases: NDArray, tips: NDArray, low: NDArray, resolution: float,
                rows: int, cols: int) -> NDArray:
    """How many rays crossed each cell before their end (sampled once a cell along each ray)."""
    misses = np.zeros(rows * cols, dtype=np.int64)
    chunk = 1024
    for first in range(0, len(bases), chunk):
        a, b = bases[first:first + chunk], tips[first:first + chunk]
        length = np.hypot(*(b - a).T)
        samples = int(math.ceil(length.max() / resolution)) if len(length) else 0
        if samples == 0:
            continue
        t = np.arange(samples) * resolution                              # (S,)
        inside = t[None, :] < length[:, None] - resolution               # stop a cell short of the end
        unit = (b - a) / np.maximum(length, 1e-9)[:, None]
        points = a[:, None, :] + unit[:, None, :] * t[None, :, None]      # (R, S, 2)
        flat = _flat_all(points, low, resolution, rows, cols)[inside]
        misses += np.bincount(flat[flat >= 0], minlength=rows * cols)
    return misses.reshape(rows, cols)


def _flat_all(points: NDArray, low: NDArray, resolution: float, rows: int, cols: int) -> NDArray:
    cell = np.floor((points - low) / resolution).astype(np.int64)
    inside = (cell[..., 0] >= 0) & (cell[..., 0] < cols) & (cell[..., 1] >= 0) & (cell[..., 1] < rows)
    return np.where(inside, cell[..., 1] * cols + cell[..., 0], -1)


def grid_walls(grid: Grid, *, tolerance: float | None = None, min_length: float | None = None) -> NDArray:
    """``(N, 4)`` wall segments along the outlines of ``grid``'s occupied regions
    (:func:`wurde_idl.gridwalls.grid_walls`).

    :param grid: the occupancy grid.
    :param tolerance: m the simplified outline may stray; None: one cell.
    :param min_length: m; a shorter outline is dropped; None: two cells.
    """
    return gridwalls.grid_walls(grid.cells, grid.origin, grid.resolution, tolerance=tolerance, min_length=min_length)
