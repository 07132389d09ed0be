"""Batched clearance geometry: how far many points or many straight legs stay from many walls.

:class:`~.world.World` answers one question at a time (the nearest wall to a point, the sweep of
one disc); the map generator and the route planner ask thousands at once (is this candidate node
free, which of these legs keeps the robot clear), so these functions take arrays and settle them
in a few whole-array numpy operations, in chunks that bound the memory.  Pure numpy, no rclpy.

Walls are ``(W, 4)`` arrays ``x1, y1, x2, y2`` in metres; points ``(N, 2)``.  A point's distance
to walls comes from :mod:`wurde_idl.segments` (its one home), re-exported here.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from wurde_idl.segments import point_clearance, point_segment_distance

__all__ = ['legs_clear', 'point_clearance', 'point_segment_distance', 'segment_distances']

#: Legs are batched by the square (of this side, metres) their middle lies in ...
_BATCH_CELL = 4.0
#: ... this many at a time.
_BATCH_LEGS = 256


def _cross(u: NDArray, v: NDArray) -> NDArray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def segment_distances(p: ArrayLike, q: ArrayLike, a: ArrayLike, b: ArrayLike) -> NDArray:
    """Smallest distance between segments ``p``-``q`` and ``a``-``b``, pair by pair.

    All four are ``(K, 2)`` (or broadcast to it); 0 where the segments cross or touch.
    """
    p, q, a, b = (np.asarray(v, dtype=np.float64) for v in (p, q, a, b))
    distance = np.minimum.reduce([point_segment_distance(p, a, b), point_segment_distance(q, a, b),
                                  point_segment_distance(a, p, q), point_segment_distance(b, p, q)])
    d1, d2 = _cross(q - p, a - p), _cross(q - p, b - p)
    d3, d4 = _cross(b - a, p - a), _cross(b - a, q - a)
    crossing = (d1 * d2 < 0.0) & (d3 * d4 < 0.0)
    return np.where(crossing, 0.0, distance)


def legs_clear(p: ArrayLike, q: ArrayLike, walls: ArrayLike, clearance: float) -> NDArray:
    """``(L,)`` booleans: whether each straight leg ``p[i]``-``q[i]`` stays more than
    ``clearance`` from every wall (a disc of that radius moved along it touches none).

    A leg from a point to itself asks whether the point is that far from every wall.  Legs are
    taken in spatially compact batches, and only the walls whose box, grown by ``clearance``,
    meets a leg's box are measured, so the work grows with the walls near each leg.
    """
    p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
    q = np.asarray(q, dtype=np.float64).reshape(-1, 2)
    segments = np.asarray(walls, dtype=np.float64).reshape(-1, 4)
    clear = np.ones(len(p), dtype=bool)
    if len(segments) == 0 or len(p) == 0:
        return clear
    wall_low = np.minimum(segments[:, 0:2], segments[:, 2:4]) - clearance
    wall_high = np.maximum(segments[:, 0:2], segments[:, 2:4]) + clearance
    leg_low, leg_high = np.minimum(p, q), np.maximum(p, q)
    cell = np.floor((p + q) / (2 * _BATCH_CELL)).astype(np.int64)
    order = np.lexsort((cell[:, 1], cell[:, 0]))
    for batch in np.array_split(order, -(-len(order) // _BATCH_LEGS)):
        low, high = leg_low[batch].min(axis=0), leg_high[batch].max(axis=0)
        nearby = np.flatnonzero(np.all((wall_low <= high) & (wall_high >= low), axis=1))
        if len(nearby) == 0:
            continue
        overlap = np.all((leg_low[batch, None, :] <= wall_high[None, nearby, :])
                         & (leg_high[batch, None, :] >= wall_low[None, nearby, :]), axis=2)
        legs, hits = np.nonzero(overlap)
        legs, hits = batch[legs], nearby[hits]
        gap = segment_distances(p[legs], q[legs], segments[hits, 0:2], segments[hits, 2:4])
        clear[legs[gap <= clearance]] = False
    return clear
