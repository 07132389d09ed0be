"""Small helpers on line segments given by their end points (metres, any frame); a point's
distance to segments is :func:`wurde_idl.segments.point_segment_distance`."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ['clip_to_disc']


def clip_to_disc(a: ArrayLike, b: ArrayLike, radius: float) -> NDArray | None:
    """``(2, 2)``: the part of segment ``ab`` within ``radius`` of the origin (None: no part)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    d = b - a
    qa, qb, qc = float(d @ d), 2.0 * float(a @ d), float(a @ a) - radius * radius
    disc = qb * qb - 4.0 * qa * qc
    if qa == 0.0 or disc <= 0.0:
        return None
    root = math.sqrt(disc)
    lo, hi = max(0.0, (-qb - root) / (2.0 * qa)), min(1.0, (-qb + root) / (2.0 * qa))
    if lo >= hi:
        return None
    return np.array([a + lo * d, a + hi * d])
