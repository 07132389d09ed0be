"""Discs and oriented boxes at one instant: the moving obstacles as the sensors and the base meet them.

The people of the simulator (:mod:`.people`) are, at any stamp, a set of discs and of boxes
turned along their walking direction.  :class:`Shapes` holds one such snapshot and answers what
:class:`~.raycast.Segments` answers for the walls, vectorised with numpy the same way:

- :meth:`Shapes.cast`: the distance along each beam to the first shape (beams x shapes arrays;
  a disc by the ray-circle quadratic, a box by the slab method in the box's own frame); a beam
  that starts inside a shape reads 0, as one starting on a wall does;
- :meth:`Shapes.nearest`: each shape's point nearest to a point, and its distance (bumpers);
- :meth:`Shapes.sweep_circle`: how much of a disc's straight move is free (the robot's step),
  with the walls' rule: a disc already touching a shape may leave it or slide, not push into it.

Every shape carries an ``id`` (the person's index), so a contact can be told to the right person.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .raycast import EPSILON, Segments

__all__ = ['Shapes']

#: The corners of a unit box, counter-clockwise, in (along, across) half-extents.
_CORNERS = np.array([(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)])


def _rays(origin: ArrayLike, angles: ArrayLike) -> tuple[NDArray, NDArray]:
    """``(B, 2)`` origins and ``(B, 2)`` unit directions; :raises ValueError: as ``Segments.cast``."""
    angles = np.asarray(angles, dtype=np.float64).reshape(-1)
    origin = np.asarray(origin, dtype=np.float64)
    if not (np.all(np.isfinite(angles)) and np.all(np.isfinite(origin))):
        raise ValueError('ray origins and angles must be finite')
    if origin.shape != (2,) and origin.shape != (angles.size, 2):
        raise ValueError(f'origin must be (2,) or ({angles.size}, 2), not {origin.shape}')
    direction = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return np.broadcast_to(origin, direction.shape), direction


class Shapes:
    """Discs and oriented boxes at one instant, read-only.

    :param discs: ``(D, 3)``: ``x, y, radius`` (m).
    :param boxes: ``(K, 5)``: ``x, y, heading, half_length, half_width`` — the centre, the
        direction the box's length lies along (rad), half its length and half its width (m).
    :param disc_ids: ``(D,)`` the id of each disc (default ``0 .. D-1``).
    :param box_ids: ``(K,)`` the id of each box (default ``D .. D+K-1``).
    :raises ValueError: a non-finite value or a size not above zero.
    """

    def __init__(self, discs: ArrayLike = (), boxes: ArrayLike = (), *,
                 disc_ids: ArrayLike | None = None, box_ids: ArrayLike | None = None) -> None:
        self.discs = np.array(discs, dtype=np.float64).reshape(-1, 3)
        self.boxes = np.array(boxes, dtype=np.float64).reshape(-1, 5)
        if not (np.all(np.isfinite(self.discs)) and np.all(np.isfinite(self.boxes))):
            raise ValueError('shapes must be finite')
        if np.any(self.discs[:, 2] <= 0.0) or np.any(self.boxes[:, 3:5] <= 0.0):
            raise ValueError('shapes must have a size above zero')
        d, k = len(self.discs), len(self.boxes)
        self.disc_ids = np.arange(d) if disc_ids is None else np.asarray(disc_ids, dtype=np.int64).reshape(d)
        self.box_ids = np.arange(d, d + k) if box_ids is None else np.asarray(box_ids, dtype=np.int64).reshape(k)
        self._cos, self._sin = np.cos(self.boxes[:, 2]), np.sin(self.boxes[:, 2])
        for item in (self.discs, self.boxes, self.disc_ids, self.box_ids, self._cos, self._sin):
            item.flags.writeable = False

    def __len__(self) -> int:
        return len(self.discs) + len(self.boxes)

    def __repr__(self) -> str:
        return f'Shapes(discs={len(self.discs)}, boxes={len(self.boxes)})'

    def centres(self) -> NDArray:
        """``(N, 2)``: every shape's centre, discs first (the order of :meth:`nearest`)."""
        return np.concatenate([self.discs[:, 0:2], self.boxes[:, 0:2]]).reshape(-1, 2)

    def box_edges(self) -> NDArray:
        """``(4K, 4)``: every box's four sides as segments ``x1, y1, x2, y2``."""
        along = np.stack([self._cos, self._sin], axis=1)[:, None, :]            # (K, 1, 2)
        across = np.stack([-self._sin, self._cos], axis=1)[:, None, :]
        corners = (self.boxes[:, None, 0:2] + _CORNERS[None, :, 0:1] * self.boxes[:, None, 3:4] * along
                   + _CORNERS[None, :, 1:2] * self.boxes[:, None, 4:5] * across)  # (K, 4, 2)
        return np.concatenate([corners, np.roll(corners, -1, axis=1)], axis=2).reshape(-1, 4)

    def _local(self, points: NDArray) -> tuple[NDArray, NDArray]:
        """``points`` ``(..., 2)`` in every box's frame: ``(..., K)`` along and across."""
        rx = points[..., 0:1] - self.boxes[:, 0]
        ry = points[..., 1:2] - self.boxes[:, 1]
        return rx * self._cos + ry * self._sin, -rx * self._sin + ry * self._cos

    # -- rays ------------------------------------------------------------------------------------

    def cast(self, origin: ArrayLike, angles: ArrayLike, max_range: float = math.inf) -> NDArray:
        """Distance along each beam to the first shape: as :meth:`Segments.cast <.raycast.Segments.cast>`.

        :returns: ``(B,)`` distances in ``[0, max_range]``; 0 for a beam starting inside a shape.
        """
        origins, direction = _rays(origin, angles)
        distance = np.full(len(direction), math.inf)
        if len(self.discs):
            np.minimum(distance, self._cast_discs(origins, direction), out=distance)
        if len(self.boxes):
            np.minimum(distance, self._cast_boxes(origins, direction), out=distance)
        return np.minimum(distance, max_range)

    def _cast_discs(self, origins: NDArray, direction: NDArray) -> NDArray:
        w = origins[:, None, :] - self.discs[None, :, 0:2]                     # (B, D, 2)
        b = np.einsum('bdk,bk->bd', w, direction)
        c = np.einsum('bdk,bdk->bd', w, w) - self.discs[:, 2] ** 2
        discriminant = b * b - c
        with np.errstate(invalid='ignore'):
            t = -b - np.sqrt(discriminant)
        hit = np.where(c <= 0.0, 0.0, np.where((discriminant >= 0.0) & (t >= 0.0), t, math.inf))
        return hit.min(axis=1)

    def _cast_boxes(self, origins: NDArray, direction: NDArray) -> NDArray:
        px, py = self._local(origins)                                          # (B, K)
        ux = direction[:, 0:1] * self._cos + direction[:, 1:2] * self._sin
        uy = -direction[:, 0:1] * self._sin + direction[:, 1:2] * self._cos
        low, high = np.full(px.shape, -math.inf), np.full(px.shape, math.inf)
        for p, u, half in ((px, ux, self.boxes[:, 3]), (py, uy, self.boxes[:, 4])):
            with np.errstate(divide='ignore', invalid='ignore', over='ignore'):
                t1, t2 = (-half - p) / u, (half - p) / u
            parallel = u == 0.0
            outside = parallel & (np.abs(p) > half)
            np.maximum(low, np.where(parallel, -math.inf, np.minimum(t1, t2)), out=low)
            np.minimum(high, np.where(parallel, math.inf, np.maximum(t1, t2)), out=high)
            high[outside] = -math.inf                                          # a parallel miss
        hit = (high >= 0.0) & (low <= high)
        return np.where(hit, np.maximum(low, 0.0), math.inf).min(axis=1)

    # -- distances -------------------------------------------------------------------------------

    def nearest(self, point: ArrayLike) -> tuple[NDArray, NDArray, NDArray]:
        """Every shape's point nearest to ``point``.

        :returns: ``(ids (N,), distances (N,), closest points (N, 2))``, discs first; the
            distance is 0 and the closest point ``point`` itself when it lies inside a shape.
        """
        p = np.asarray(point, dtype=np.float64).reshape(2)
        offset = p - self.discs[:, 0:2]                                        # (D, 2)
        gap = np.hypot(offset[:, 0], offset[:, 1])
        radius = self.discs[:, 2]
        inside = gap <= radius
        scale = np.where(inside, 1.0, radius / np.where(gap > 0.0, gap, 1.0))
        disc_points = np.where(inside[:, None], p, self.discs[:, 0:2] + scale[:, None] * offset)
        along, across = (v.reshape(-1) for v in self._local(p[None, :]))
        qa = np.clip(along, -self.boxes[:, 3], self.boxes[:, 3])
        qc = np.clip(across, -self.boxes[:, 4], self.boxes[:, 4])
        box_points = self.boxes[:, 0:2] + np.stack([qa * self._cos - qc * self._sin,
                                                    qa * self._sin + qc * self._cos], axis=1)
        box_gap = np.hypot(along - qa, across - qc)
        return (np.concatenate([self.disc_ids, self.box_ids]),
                np.concatenate([np.maximum(gap - radius, 0.0), box_gap]),
                np.concatenate([disc_points, box_points]).reshape(-1, 2))

    # -- moving discs ----------------------------------------------------------------------------

    def sweep_circle(self, start: ArrayLike, end: ArrayLike, radius: float) -> float:
        """How much of the straight move of a disc of ``radius`` from ``start`` to ``end`` is
        free of the shapes, as :meth:`Segments.sweep_circle <.raycast.Segments.sweep_circle>`.

        :returns: the fraction in ``[0, 1]``; 0.0 for a move into a shape the disc touches.
        """
        start = np.asarray(start, dtype=np.float64).reshape(2)
        end = np.asarray(end, dtype=np.float64).reshape(2)
        move = end - start
        if not move.any() or len(self) == 0:
            return 1.0
        best = 1.0
        if len(self.discs):
            best = self._sweep_discs(start, move, radius)
        if len(self.boxes) and best > 0.0:
            best = min(best, Segments(self.box_edges()).sweep_circle(start, end, radius))
        return best

    def _sweep_discs(self, start: NDArray, move: NDArray, radius: float) -> float:
        """The round people: a disc of ``radius`` against discs grown by it (a quadratic each)."""
        reach = self.discs[:, 2] + radius
        relative = start - self.discs[:, 0:2]                                  # (D, 2)
        gap2 = np.einsum('dk,dk->d', relative, relative)
        touching = gap2 <= (reach + EPSILON) ** 2
        if np.any(touching & (relative @ move < -EPSILON * math.hypot(*move))):
            return 0.0                                                         # into one it touches
        a = float(move @ move)
        b = 2.0 * (relative @ move)
        c = gap2 - reach * reach
        discriminant = b * b - 4.0 * a * c
        ok = (discriminant >= 0.0) & ~touching
        if not ok.any():
            return 1.0
        t = (-b[ok] - np.sqrt(discriminant[ok])) / (2.0 * a)
        t = t[(t >= 0.0) & (t <= 1.0)]
        return float(t.min()) if t.size else 1.0
