"""The a priori map of Pluto's poseModule (Pluto 7.1): walls as line segments in the map frame.

Each wall is kept as its infinite line in normal form ``(gamma, rho)`` (``rho >= 0``, seen from
the map's origin) and its extent along that line: positions ``t`` along the direction
``(-sin gamma, cos gamma)``, measured from the foot of the perpendicular from the origin.  Walls
are two-sided (a map segment has no inside), so a sensor on either side can see one.

Building a map compares every wall with every other to find collinear ones: quadratic, meant for
maps of up to a few thousand walls.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['CHAIN_GAP', 'COLLINEAR_ANGLE', 'COLLINEAR_DISTANCE', 'DEFAULT_MIN_FACING_DISTANCE',
           'WallMap']

#: m: a sensor closer than this to a wall's line sees it edge-on, not facing it.
DEFAULT_MIN_FACING_DISTANCE = 0.05
#: Walls whose lines differ by less than this (rad, m) lie on one line (see ``WallMap.line``).
COLLINEAR_ANGLE = 0.01
COLLINEAR_DISTANCE = 0.02
#: m: collinear walls closer than this end to end form one chain (no gap a laser sees through).
CHAIN_GAP = 0.05


class WallMap:
    """Walls of a map, with their lines and extents.

    :param walls: ``(N, 4)`` segments ``x1, y1, x2, y2`` in metres in the map frame.
    :raises ValueError: on a malformed array, a non-finite coordinate or a zero-length wall
        (naming the wall's row).
    """

    def __init__(self, walls: ArrayLike) -> None:
        """Each wall's line and extent, the collinear walls and the chains they form.

        :param walls: ``(N, 4)`` segments ``x1, y1, x2, y2`` in metres in the map frame.
        :raises ValueError: on a malformed array, a non-finite coordinate or a zero-length wall
            (naming the wall's row).
        """
        segments = np.array(walls, dtype=np.float64)
        if segments.size == 0:
            segments = segments.reshape(0, 4)
        if segments.ndim != 2 or segments.shape[1] != 4:
            raise ValueError(f'walls must be an (N, 4) array of x1, y1, x2, y2, not shape '
                             f'{segments.shape}')
        bad = ~np.isfinite(segments).all(axis=1)
        if bad.any():
            raise ValueError(f'wall {int(np.argmax(bad))} has a non-finite coordinate')
        delta = segments[:, 2:4] - segments[:, 0:2]
        length = np.hypot(delta[:, 0], delta[:, 1])
        if (length == 0.0).any():
            raise ValueError(f'wall {int(np.argmin(length))} has zero length')
        direction = delta / length[:, None]
        normal = np.column_stack([direction[:, 1], -direction[:, 0]])
        rho = np.einsum('ij,ij->i', segments[:, 0:2], normal)
        normal[rho < 0.0] *= -1.0
        segments.flags.writeable = False
        #: ``(N, 4)`` the segments as given.
        self.walls: NDArray = segments
        #: ``(N,)`` normal direction (rad) and distance (m) of each wall's line from the origin.
        self.gamma: NDArray = np.arctan2(normal[:, 1], normal[:, 0])
        self.rho: NDArray = np.abs(rho)
        #: ``(N,)`` ``cos(gamma)``, ``sin(gamma)``: the unit normal.
        self.cos_gamma: NDArray = normal[:, 0].copy()
        self.sin_gamma: NDArray = normal[:, 1].copy()
        #: ``(N,)`` m: length of each wall.
        self.length: NDArray = length
        along = np.column_stack([-normal[:, 1], normal[:, 0]])
        #: ``(2, N)`` the direction ``(-sin gamma, cos gamma)`` of each wall, as columns.
        self.along: NDArray = along.T.copy()
        t1 = np.einsum('ij,ij->i', segments[:, 0:2], along)
        t2 = np.einsum('ij,ij->i', segments[:, 2:4], along)
        #: ``(N, 2)`` extent ``[t_min, t_max]`` of each wall along ``(-sin gamma, cos gamma)``.
        self.extent: NDArray = np.column_stack([np.minimum(t1, t2), np.maximum(t1, t2)])
        #: ``(N,)`` walls on one infinite line (within ``COLLINEAR_*``) share a number: a line
        #: seen on any of them is the same measurement (a wall drawn in pieces, a row of walls
        #: between doors).
        self.line: NDArray = _collinear_groups(self.gamma, self.rho)
        #: ``(N, 2)`` extent, like :attr:`extent`, of the chain of collinear walls that touch
        #: (less than ``CHAIN_GAP`` apart) the wall: what a laser sees as one straight wall.
        self.chain_extent: NDArray = _chains(self.line, along, self.extent, segments)
        #: ``(N,)`` m: length of that chain.
        self.chain_length: NDArray = self.chain_extent[:, 1] - self.chain_extent[:, 0]
        self._ends_x = segments[:, 0::2].copy()
        self._ends_y = segments[:, 1::2].copy()
        xs, ys = self._ends_x.reshape(-1), self._ends_y.reshape(-1)
        self._box = (float(xs.min()), float(ys.min()), float(xs.max()), float(ys.max())) \
            if len(xs) else (0.0, 0.0, 0.0, 0.0)

    def __len__(self) -> int:
        return len(self.walls)

    def __repr__(self) -> str:
        return f'WallMap({len(self)} walls)'

    def visible(self, pose: ArrayLike, max_range: float, *, margin: float = 0.0,
                min_distance: float = DEFAULT_MIN_FACING_DISTANCE) -> NDArray:
        """Indices of the walls a laser at ``pose`` can plausibly see.

        Plausible means *in range*: some point of the wall is closer than ``max_range + margin``;
        *in the field of view*: some point of it is in front of the laser (its x in the laser
        frame above ``-margin``; the SICK sees the half-plane ahead); and *facing it*: the laser
        is at least ``min_distance`` from the wall's line, so it does not see the wall edge-on.
        Occlusion is not considered (the matcher's overlap test and gate deal with hidden walls).

        :param pose: the laser pose ``(x, y, theta)`` in the map frame.
        :param max_range: m, the laser's range.
        :param margin: m, slack for the uncertainty of ``pose``.
        :param min_distance: m the laser must be from a wall's line.
        """
        x, y, theta = np.asarray(pose, dtype=np.float64).reshape(3).tolist()
        c, s = math.cos(theta), math.sin(theta)
        # x of both ends in the laser frame: the ends' projections on (c, s) less the laser's.
        forward = self._ends_x * c + self._ends_y * s - (x * c + y * s)
        plausible = (forward.max(axis=1) > -margin) & \
            (np.abs(self.rho - x * self.cos_gamma - y * self.sin_gamma) >= min_distance)
        if self._farthest(x, y) >= max_range + margin:
            # Some walls may be out of range: the distance from the laser to each segment.
            w = self.walls
            ax, ay, dx, dy = w[:, 0] - x, w[:, 1] - y, w[:, 2] - w[:, 0], w[:, 3] - w[:, 1]
            t = np.clip(-(ax * dx + ay * dy) / (self.length * self.length), 0.0, 1.0)
            plausible &= np.hypot(ax + t * dx, ay + t * dy) < max_range + margin
        return plausible.nonzero()[0]

    def _farthest(self, x: float, y: float) -> float:
        """Distance from ``(x, y)`` to the farthest corner of the box around all walls."""
        xmin, ymin, xmax, ymax = self._box
        return math.hypot(max(x - xmin, xmax - x), max(y - ymin, ymax - y))


def _collinear_groups(gamma: NDArray, rho: NDArray) -> NDArray:
    """Label walls whose lines coincide (connected components of "collinear"), ``0..K-1``."""
    if len(gamma) == 0:
        return np.zeros(0, dtype=np.int64)
    turn = np.abs(np.mod(gamma[:, None] - gamma[None, :] + math.pi, 2.0 * math.pi) - math.pi)
    same = (turn < COLLINEAR_ANGLE) & (np.abs(rho[:, None] - rho[None, :]) < COLLINEAR_DISTANCE)
    # A line through the origin may come out with either normal: gamma and gamma + pi.
    same |= (np.abs(turn - math.pi) < COLLINEAR_ANGLE) & \
        (rho[:, None] + rho[None, :] < COLLINEAR_DISTANCE)
    labels = np.arange(len(gamma))
    while True:
        spread = np.where(same, labels[None, :], len(gamma)).min(axis=1)
        if np.array_equal(spread, labels):
            break
        labels = spread
    return np.unique(labels, return_inverse=True)[1].reshape(-1)


def _chains(line: NDArray, along: NDArray, extent: NDArray, segments: NDArray) -> NDArray:
    """Each wall's chain extent (see ``WallMap.chain_extent``), in the wall's own ``t``."""
    chain = extent.copy()
    for group in np.flatnonzero(np.bincount(line) > 1):
        members = np.flatnonzero(line == group)
        axis = along[members[0]]
        # Every member's interval on the first member's axis.
        t = np.sort(np.column_stack([segments[members, 0:2] @ axis,
                                     segments[members, 2:4] @ axis]), axis=1)
        order = np.argsort(t[:, 0])
        low, high, runs = t[order[0], 0], t[order[0], 1], []
        for k in order[1:]:
            if t[k, 0] <= high + CHAIN_GAP:
                high = max(high, t[k, 1])
            else:
                runs.append((low, high))
                low, high = t[k, 0], t[k, 1]
        runs.append((low, high))
        for k, wall in enumerate(members):
            low, high = next(run for run in runs if run[0] <= t[k, 0] and t[k, 1] <= run[1])
            if along[wall] @ axis < 0.0:                 # this wall's t runs the other way
                low, high = -high, -low
            shift = extent[wall, 0] - (t[k, 0] if along[wall] @ axis > 0.0 else -t[k, 1])
            chain[wall] = (low + shift, high + shift)
    return chain
