"""What a laser has seen, as points to match the next scan against: :class:`PointMap`.

The graph SLAM (:mod:`.graph_slam`) and the grid localizer match a scan against a map made of
many scans' points.  A :class:`PointMap` holds those points with what both matching steps need:

- a *likelihood field* for the correlative search (:mod:`.correlative`): a grid of
  ``exp(-d^2 / (2 sigma^2))``, ``d`` the distance to the nearest map point (Thrun, Burgard and
  Fox's likelihood field; Olson's correlative scan matching scores a pose by the sum of the field
  under the scan's points), with coarser copies whose cells hold the largest value beneath them,
  so a coarse score is an upper bound of the fine scores it covers;
- a k-d tree and each point's normal (the direction of least spread of its neighbours) for
  point-to-line ICP (:mod:`.icp`).

Points are first reduced to one per ``voxel`` cell (:func:`voxel_filter`) so that a wall seen by
fifty scans counts no more than one seen by two.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage
from scipy.spatial import cKDTree

__all__ = ['PointMap', 'voxel_filter']

#: Neighbours a normal is fitted to.
NORMAL_NEIGHBOURS = 7
#: m of empty border round the points in the likelihood field.
BORDER = 1.0


def voxel_filter(points: ArrayLike, size: float) -> NDArray:
    """The first point of each ``size`` x ``size`` cell, in the points' order (deterministic).

    :param points: ``(N, 2)`` metres.
    :param size: m, the cell's side.
    """
    xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(xy) == 0:
        return xy
    cells = np.floor(xy / size).astype(np.int64)
    keys = (cells[:, 0] << 32) ^ (cells[:, 1] & 0xFFFFFFFF)
    _, first = np.unique(keys, return_index=True)
    return xy[np.sort(first)]


class PointMap:
    """Points in one frame, ready for the correlative search and ICP.

    :param points: ``(N, 2)`` metres, at least :data:`NORMAL_NEIGHBOURS`.
    :param resolution: m per cell of the likelihood field.
    :param sigma: m, the field's spread: about the scans' noise plus the map's blur.
    :raises ValueError: too few points.
    """

    def __init__(self, points: ArrayLike, *, resolution: float = 0.05, sigma: float = 0.08) -> None:
        """Index the points and compute each one's normal (the field is computed when first asked).

        :param points: ``(N, 2)`` metres, at least :data:`NORMAL_NEIGHBOURS`.
        :param resolution: m per cell of the likelihood field.
        :param sigma: m, the field's spread.
        :raises ValueError: too few points.
        """
        self.points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if len(self.points) < NORMAL_NEIGHBOURS:
            raise ValueError(f'a point map needs {NORMAL_NEIGHBOURS} points or more, not {len(self.points)}')
        self.resolution, self.sigma = float(resolution), float(sigma)
        self.tree = cKDTree(self.points)
        self.normals = self._normals()
        self.origin = self.points.min(axis=0) - BORDER
        self._fields: dict[int, NDArray] = {}

    def _normals(self) -> NDArray:
        _, neighbours = self.tree.query(self.points, k=NORMAL_NEIGHBOURS)
        around = self.points[neighbours]
        around = around - around.mean(axis=1, keepdims=True)
        scatter = np.einsum('nki,nkj->nij', around, around)
        _, vectors = np.linalg.eigh(scatter)
        return vectors[:, :, 0]                    # the direction of least spread

    def field(self, factor: int = 1) -> NDArray:
        """The likelihood field at ``factor`` times the resolution.

        :param factor: the cell size in fine cells; a coarse cell holds the largest value of the fine
            cells beneath (computed once, then kept).
        :returns: ``field[i, j]`` for the cell ``origin + (i, j) * resolution * factor``, values in (0, 1].
        """
        if factor not in self._fields:
            if factor == 1:
                self._fields[1] = self._fine_field()
            else:
                fine = self.field(1)
                pad = (-fine.shape[0] % factor, -fine.shape[1] % factor)
                grid = np.pad(fine, ((0, pad[0]), (0, pad[1])))
                self._fields[factor] = grid.reshape(grid.shape[0] // factor, factor,
                                                    grid.shape[1] // factor, factor).max(axis=(1, 3))
        return self._fields[factor]

    def _fine_field(self) -> NDArray:
        top = self.points.max(axis=0) + BORDER
        shape = np.ceil((top - self.origin) / self.resolution).astype(int) + 1
        empty = np.ones(shape, dtype=bool)
        cells = np.floor((self.points - self.origin) / self.resolution).astype(int)
        empty[cells[:, 0], cells[:, 1]] = False
        distance = ndimage.distance_transform_edt(empty) * self.resolution
        return np.exp(-0.5 * np.square(distance / self.sigma))

    def nearest(self, points: NDArray, max_distance: float) -> tuple[NDArray, NDArray]:
        """Distance to, and index of, each point's nearest map point.

        :param points: ``(M, 2)`` metres, in the map's frame.
        :param max_distance: m; a point with no map point this near gets ``inf`` and ``len(map)``.
        """
        return self.tree.query(points, distance_upper_bound=max_distance)

    def __len__(self) -> int:
        return len(self.points)

    @property
    def extent(self) -> float:
        """m: the diagonal of the points' bounding box."""
        return float(math.hypot(*(self.points.max(axis=0) - self.points.min(axis=0))))
