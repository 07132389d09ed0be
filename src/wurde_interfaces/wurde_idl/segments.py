"""Distances from points to line segments: the one home of this geometry for every package (the
map's walls, a plan's legs, a SLAM map's lines).  Pure numpy.

Segments are given by their ends ``a``, ``b`` (``(..., 2)``) or as rows ``x1, y1, x2, y2``
(``(S, 4)``); metres in any frame.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['point_clearance', 'point_segment_distance']

#: Largest number of (point, segment) pairs handled in one array operation.
_CHUNK_PAIRS = 1 << 20


def point_segment_distance(points: ArrayLike, a: ArrayLike, b: ArrayLike) -> NDArray:
    """Distance from each of ``points`` to the segment ``a``-``b``; a segment of no length is
    its point.  The three arrays broadcast against each other.

    :param points: ``(..., 2)`` points.
    :param a: ``(..., 2)`` first ends of the segments.
    :param b: ``(..., 2)`` second ends.
    :returns: the distances, in the broadcast shape without the last axis.
    """
    points, a, b = (np.asarray(v, dtype=np.float64) for v in (points, a, b))
    ex, ey = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
    px, py = points[..., 0] - a[..., 0], points[..., 1] - a[..., 1]
    length2 = ex * ex + ey * ey
    t = np.clip((px * ex + py * ey) / np.where(length2 > 0.0, length2, 1.0), 0.0, 1.0)
    return np.hypot(px - t * ex, py - t * ey)


def point_clearance(points: ArrayLike, segments: ArrayLike) -> NDArray:
    """The distance from each point to the nearest segment, in chunks that bound the memory.

    :param points: ``(N, 2)`` (any shape with pairs last is flattened to that).
    :param segments: ``(S, 4)`` rows ``x1, y1, x2, y2``.
    :returns: ``(N,)`` distances; ``inf`` for each point when there is no segment.
    """
    xy = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    rows = np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    result = np.full(len(xy), np.inf)
    if len(rows) == 0:
        return result
    step = max(1, _CHUNK_PAIRS // len(rows))
    a, b = rows[None, :, 0:2], rows[None, :, 2:4]
    for start in range(0, len(xy), step):
        result[start:start + step] = point_segment_distance(xy[start:start + step, None, :], a, b).min(axis=1)
    return result
