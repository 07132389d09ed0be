"""Casting rays and moving discs against a fixed set of line segments, vectorised with numpy.

:class:`Segments` precomputes everything that depends only on the walls (start points, edge vectors,
lengths), so one scan is a handful of whole-array operations over a beams x segments matrix:
361 beams against 200 segments is a 361 x 200 problem that numpy settles in a fraction of a
millisecond (``bench/raycast.py`` measures it; the issue's goal is 500 scans/s on one core).

Geometry: a ray ``o + t d`` (``d`` a unit vector, ``t >= 0``) meets a segment ``p + s e``
(``0 <= s <= 1``) where ``t = (w x e) / (d x e)`` and ``s = (w x d) / (d x e)`` with ``w = p - o``
and ``a x b`` the 2D cross product.  Where ``d x e`` is zero the ray is parallel to the segment and
misses it, unless the origin lies on the segment's line (collinear): then the ray first touches the
segment at its nearer end, or at once (distance 0) when the origin is on the segment itself.
"""

from __future__ import annotations

import math
import threading

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['EPSILON', 'Segments']

#: Metres: an origin closer than this to a segment's line counts as lying on it.
EPSILON = 1e-9

#: Stands for 'no hit' inside the kernel; any real distance is far below it.
_FAR = 1e300


class _Workspace:
    """Preallocated (beams x segments) arrays for one scan."""

    def __init__(self, beams: int, segments: int) -> None:
        self.denominator = np.empty((beams, segments))
        self.t = np.empty((beams, segments))
        self.s = np.empty((beams, segments))
        self.miss = np.empty((beams, segments), dtype=bool)
        self.scratch = np.empty((beams, segments), dtype=bool)


class Segments:
    """Walls as an (N, 4) array ``x1, y1, x2, y2`` (metres), ready for ray and disc casting.

    The walls are read-only, so sensors may share one object; the scratch buffers of
    :meth:`cast` are kept per thread, so threads may cast at the same time.
    """

    def __init__(self, walls: ArrayLike) -> None:
        array = np.array(walls, dtype=np.float64).reshape(-1, 4)
        self.walls = array
        self.start = array[:, 0:2].copy()
        self.edge = array[:, 2:4] - array[:, 0:2]
        self.length = np.hypot(self.edge[:, 0], self.edge[:, 1])
        # d x e = dx*ey - dy*ex = d @ [ey, -ex]: one small matrix product per scan.
        self._cross_matrix = np.vstack([self.edge[:, 1], -self.edge[:, 0]])
        self._local = threading.local()
        for item in (self.walls, self.start, self.edge, self.length, self._cross_matrix):
            item.flags.writeable = False

    def _workspace(self, beams: int) -> _Workspace:
        """Buffers for a scan of ``beams`` beams, one set per thread and beam count."""
        cache: dict[int, _Workspace] = self._local.__dict__.setdefault('cache', {})
        work = cache.get(beams)
        if work is None:
            if len(cache) > 8:
                cache.clear()
            work = cache[beams] = _Workspace(beams, len(self.walls))
        return work

    def __len__(self) -> int:
        return len(self.walls)

    # -- rays ------------------------------------------------------------------------------------

    def cast(self, origin: ArrayLike, angles: ArrayLike, max_range: float = math.inf) -> NDArray:
        """Distance along each beam from ``origin`` to the first segment it meets.

        :param origin: ``(x, y)`` shared by all beams, or an ``(B, 2)`` array, one per beam.
        :param angles: ``(B,)`` beam directions in radians, world frame (0 along +x, CCW).
        :param max_range: returned for beams that meet nothing closer (``inf`` by default).
        :returns: ``(B,)`` float64 distances in metres, each in ``[0, max_range]``.
        :raises ValueError: for a non-finite origin or angle, or an origin of the wrong shape.
        """
        angles = np.asarray(angles, dtype=np.float64).reshape(-1)
        origin = np.asarray(origin, dtype=np.float64)
        if not (np.all(np.isfinite(angles)) and np.all(np.isfinite(origin))):
            raise ValueError('ray origins and angles must be finite')
        if len(self.walls) == 0 or angles.size == 0:
            return np.full(angles.shape, max_range, dtype=np.float64)
        direction = np.stack([np.cos(angles), np.sin(angles)], axis=1)        # (B, 2)
        work = self._workspace(angles.size)
        denominator = np.matmul(direction, self._cross_matrix, out=work.denominator)  # d x e
        if origin.shape == (2,):
            offset = self.start - origin                                      # (S, 2): w
            w_cross_e = offset[:, 0] * self.edge[:, 1] - offset[:, 1] * self.edge[:, 0]  # (S,)
            # w x d = wx*dy - wy*dx = d @ [-wy, wx]
            w_cross_d = np.matmul(direction, np.vstack([-offset[:, 1], offset[:, 0]]),
                                  out=work.s)
            on_line = np.nonzero(np.abs(w_cross_e) <= EPSILON * self.length)[0]
        elif origin.shape == (angles.size, 2):
            offset = self.start[None, :, :] - origin[:, None, :]              # (B, S, 2)
            w_cross_e = offset[..., 0] * self.edge[:, 1] - offset[..., 1] * self.edge[:, 0]
            w_cross_d = offset[..., 0] * direction[:, 1:2] - offset[..., 1] * direction[:, 0:1]
            on_line = np.nonzero((np.abs(w_cross_e) <= EPSILON * self.length).any(axis=0))[0]
        else:
            raise ValueError(f'origin must be (2,) or ({angles.size}, 2), not {origin.shape}')
        # In place on preallocated buffers: fresh 0.5 MB arrays cost a page fault per page,
        # which doubled the time of a scan.  Branch-free masking: a boolean index over a
        # random mask is ten times slower, so misses get a huge penalty instead.
        with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
            inverse = np.divide(1.0, denominator, out=denominator)
            t = np.multiply(w_cross_e, inverse, out=work.t)
            s = np.multiply(w_cross_d, inverse, out=work.s)
            miss = np.less(t, 0.0, out=work.miss)
            miss |= np.less(s, 0.0, out=work.scratch)
            miss |= np.greater(s, 1.0, out=work.scratch)
            penalty = np.multiply(miss, _FAR, out=work.s)
            np.maximum(t, penalty, out=t)
        if on_line.size:
            self._collinear(t, origin, direction, on_line)
        distance = t.min(axis=1)
        distance[~(distance < _FAR)] = math.inf  # also NaN, which only 0/0 can make
        np.minimum(distance, max_range, out=distance)
        return distance

    def _collinear(self, t: NDArray, origin: NDArray, direction: NDArray,
                   columns: NDArray) -> None:
        """Fix ``t`` in place for beams that run along a segment whose line holds the origin."""
        origins = np.broadcast_to(origin, (len(direction), 2))
        start = self.start[columns]                                           # (C, 2)
        end = start + self.edge[columns]
        length = self.length[columns]
        offset = start[None, :, :] - origins[:, None, :]                      # (B, C, 2)
        distance_to_line = np.abs(offset[..., 0] * self.edge[columns, 1]
                                  - offset[..., 1] * self.edge[columns, 0]) / length
        sine = np.abs(direction @ self._cross_matrix[:, columns]) / length    # |sin| (B, C)
        along = (distance_to_line <= EPSILON) & (sine <= EPSILON)
        if not along.any():
            return
        t_start = np.einsum('bck,bk->bc', offset, direction)
        t_end = np.einsum('bck,bk->bc', end[None, :, :] - origins[:, None, :], direction)
        near, far = np.minimum(t_start, t_end), np.maximum(t_start, t_end)
        hit = np.where(near >= 0.0, near, np.where(far >= 0.0, 0.0, math.inf))
        block = t[:, columns]
        block[along] = hit[along]  # authoritative: the general formula is 0/0 there
        t[:, columns] = block

    # -- distances -------------------------------------------------------------------------------

    def nearest(self, point: ArrayLike) -> tuple[float, NDArray, int]:
        """The wall nearest to ``point``: ``(distance, closest point (2,), wall index)``.

        With no walls: ``(inf, point, -1)``.
        """
        point = np.asarray(point, dtype=np.float64).reshape(2)
        if len(self.walls) == 0:
            return math.inf, point.copy(), -1
        closest = self.closest_points(point)
        gaps = np.hypot(closest[:, 0] - point[0], closest[:, 1] - point[1])
        index = int(np.argmin(gaps))
        return float(gaps[index]), closest[index], index

    def closest_points(self, point: NDArray) -> NDArray:
        """``(S, 2)``: the point of each segment closest to ``point``."""
        relative = point - self.start
        fraction = np.einsum('sk,sk->s', relative, self.edge) / (self.length ** 2)
        np.clip(fraction, 0.0, 1.0, out=fraction)
        return self.start + fraction[:, None] * self.edge

    def intersects(self, p: ArrayLike, q: ArrayLike) -> bool:
        """Whether the closed segment ``p``-``q`` touches or crosses any wall."""
        p = np.asarray(p, dtype=np.float64).reshape(2)
        q = np.asarray(q, dtype=np.float64).reshape(2)
        if len(self.walls) == 0:
            return False
        if np.array_equal(p, q):
            return self.nearest(p)[0] <= EPSILON
        move = q - p
        # A proper crossing first; failing that (parallel, collinear overlap, an end resting on
        # a wall) they touch exactly when their distance is zero.
        offset = self.start - p
        denominator = move[0] * self.edge[:, 1] - move[1] * self.edge[:, 0]
        with np.errstate(divide='ignore', invalid='ignore'):
            t = (offset[:, 0] * self.edge[:, 1] - offset[:, 1] * self.edge[:, 0]) / denominator
            s = (offset[:, 0] * move[1] - offset[:, 1] * move[0]) / denominator
        if np.any((t >= 0) & (t <= 1) & (s >= 0) & (s <= 1)):
            return True
        return self.segment_distance(p, q) <= EPSILON

    def segment_distance(self, p: NDArray, q: NDArray) -> float:
        """Smallest distance between segment ``p``-``q`` and any wall, assuming none crosses it."""
        ends = [float(np.min(np.hypot(*(self.closest_points(x) - x).T))) for x in (p, q)]
        move = q - p
        length2 = float(move @ move)
        for points in (self.start, self.start + self.edge):
            if length2 == 0.0:
                break
            fraction = np.clip(((points - p) @ move) / length2, 0.0, 1.0)
            closest = p + fraction[:, None] * move
            ends.append(float(np.min(np.hypot(*(points - closest).T))))
        return min(ends)

    # -- moving discs ----------------------------------------------------------------------------

    def sweep_circle(self, start: ArrayLike, end: ArrayLike, radius: float) -> float:
        """How far a disc of ``radius`` can move from ``start`` towards ``end`` before it touches.

        :returns: the fraction of the move in ``[0, 1]``: 1.0 when the whole move is free.  A disc
            already touching a wall may slide along it or leave it, but not move further into it
            (fraction 0.0).
        """
        start = np.asarray(start, dtype=np.float64).reshape(2)
        end = np.asarray(end, dtype=np.float64).reshape(2)
        move = end - start
        if len(self.walls) == 0 or not move.any():
            return 1.0
        closest = self.closest_points(start)
        towards = closest - start
        gaps = np.hypot(towards[:, 0], towards[:, 1])
        touching = gaps <= radius + EPSILON
        if np.any(touching & (towards @ move > EPSILON * np.hypot(*move))):
            return 0.0
        best = 1.0
        # The two long sides of each wall's capsule: the wall shifted by +-radius along its normal.
        normal = np.stack([-self.edge[:, 1], self.edge[:, 0]], axis=1) / self.length[:, None]
        for side in (1.0, -1.0):
            shifted = self.start + side * radius * normal - start
            denominator = move[0] * self.edge[:, 1] - move[1] * self.edge[:, 0]
            entering = (move @ normal.T) * side < 0.0
            with np.errstate(divide='ignore', invalid='ignore'):
                t = (shifted[:, 0] * self.edge[:, 1]
                     - shifted[:, 1] * self.edge[:, 0]) / denominator
                s = (shifted[:, 0] * move[1] - shifted[:, 1] * move[0]) / denominator
            hit = entering & ~touching & (t >= 0) & (t <= 1) & (s >= 0) & (s <= 1)
            if hit.any():
                best = min(best, float(t[hit].min()))
        # The round caps: circles of ``radius`` around both ends of each wall.
        a = float(move @ move)
        for centres in (self.start, self.start + self.edge):
            relative = start - centres
            b = 2.0 * (relative @ move)
            c = np.einsum('sk,sk->s', relative, relative) - radius * radius
            discriminant = b * b - 4.0 * a * c
            ok = (discriminant >= 0.0) & (c > 0.0) & ~touching
            if ok.any():
                t = (-b[ok] - np.sqrt(discriminant[ok])) / (2.0 * a)
                t = t[(t >= 0.0) & (t <= 1.0)]
                if t.size:
                    best = min(best, float(t.min()))
        return max(0.0, best)
